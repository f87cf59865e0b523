// Static obstacle surfaces from files: a Gmsh mesh's lines (2D) or the
// boundary of its cells, a Wavefront OBJ (polygons split into triangles), an
// ASCII STL (through Gmsh); the total length / area of what was read, and
// clear errors for a missing file, a corrupt file, an unknown format and a
// 2D file off the plane z = 0.

#include <forma/ipc/obstacle_mesh.h>

#include "../tests.h"

#include <fstream>
#include <sstream>

using namespace forma::ipc;

double
measure(const ObstacleMesh &m)
{
  double s = 0;
  for (const auto &e : m.edges)
    s += (m.vertices[e[1]] - m.vertices[e[0]]).norm();
  for (const auto &f : m.faces)
    s += 0.5 * cross_product_3d(m.vertices[f[1]] - m.vertices[f[0]],
                                m.vertices[f[2]] - m.vertices[f[0]])
                 .norm();
  return s;
}

void
report(const std::string &name, const ObstacleMesh &m)
{
  dealii::deallog << name << ": " << m.vertices.size() << " vertices, "
                  << m.edges.size() << " segments, " << m.faces.size()
                  << " triangles, measure " << measure(m) << std::endl;
}

void
expect_error(const std::string &name,
             const std::string &file,
             const unsigned int dim)
{
  try
    {
      read_obstacle_mesh(file, dim);
      dealii::deallog << name << ": no error" << std::endl;
    }
  catch (const dealii::ExceptionBase &e)
    {
      // The message, its line breaks and indentation collapsed.
      std::ostringstream s;
      e.print_info(s);
      std::istringstream in(s.str());
      std::string        word, what;
      while (in >> word)
        what += (what.empty() ? "" : " ") + word;
      dealii::deallog << name << ": " << what << std::endl;
    }
}

int
main()
{
  initlog();
  // A unit square of two triangles (no line elements): its boundary.
  std::ofstream("square.msh")
    << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n4\n"
       "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n$EndNodes\n$Elements\n2\n"
       "1 2 2 0 1 1 2 3\n2 2 2 0 1 1 3 4\n$EndElements\n";
  report("square.msh, 2D (boundary of the cells)",
         read_obstacle_mesh("square.msh", 2));
  report("square.msh, 3D (its triangles)", read_obstacle_mesh("square.msh", 3));
  // An open box of quads (5 faces of the unit cube) and a polyline.
  std::ofstream("box.obj") << "# open box\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                              "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
                              "f 1 2 3 4\nf 1 2 6 5\nf 2/1 3/1 7/1 6/1\n"
                              "f 3 4 8 7\nf -4 -1 4 1\nl 1 2 3\n";
  report("box.obj, 3D", read_obstacle_mesh("box.obj", 3));
  report("box.obj, 2D (the polyline)", read_obstacle_mesh("box.obj", 2));
  // A tetrahedron's surface in ASCII STL.
  std::ofstream("tet.stl")
    << "solid t\n"
       "facet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n"
       "facet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
       "facet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n"
       "facet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\n"
       "endsolid t\n";
  report("tet.stl, 3D", read_obstacle_mesh("tet.stl", 3));

  // A comment after a face, a degenerate (repeated corner) face dropped.
  std::ofstream("quad.obj") << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                               "f 1 2 3 4 # a square\nf 1 2 2\n";
  report("quad.obj, 3D (degenerate face dropped)",
         read_obstacle_mesh("quad.obj", 3));

  expect_error("missing file", "missing.msh", 2);
  std::ofstream("corrupt.msh")
    << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n3\n1 0 0\n";
  try
    {
      read_obstacle_mesh("corrupt.msh", 2);
      dealii::deallog << "corrupt.msh: no error" << std::endl;
    }
  catch (const dealii::ExceptionBase &)
    {
      dealii::deallog << "corrupt.msh: rejected" << std::endl;
    }
  std::ofstream("data.txt") << "1 2 3\n";
  expect_error("unknown format", "data.txt", 2);
  std::ofstream("tilted.obj") << "v 0 0 0\nv 1 0 1\nl 1 2\n";
  expect_error("2D obstacle off z = 0", "tilted.obj", 2);
}
