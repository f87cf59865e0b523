#include <deal.II/base/exceptions.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/tria.h>

#include <forma/mesh/mesh.h>
#include <forma/mesh/quad_mesh.h>

#include "gmsh_session.h"
#include <gmsh.h>

#include <filesystem>
#include <sstream>
#include <vector>

namespace forma
{
  using namespace dealii;

  void
  gmsh_quad_mesh(const std::string   &geo_file,
                 const double         element_size,
                 Triangulation<2, 2> &tria)
  {
    const std::string where = "quad mesh of '" + geo_file + "'";
    AssertThrow(std::filesystem::exists(geo_file),
                ExcMessage(where + ": the file does not exist."));
    AssertThrow(element_size > 0,
                ExcMessage(where + ": the element size must be positive."));
    std::string text;
    {
      std::lock_guard<std::mutex> lock(internal::gmsh_mutex());
      internal::GmshSession       session("quads");
      try
        {
          gmsh::open(geo_file);
        }
      catch (...)
        {
          AssertThrow(
            false, ExcMessage(internal::gmsh_error(where, "cannot read it")));
        }
      gmsh::vectorpair physicals;
      gmsh::model::getPhysicalGroups(physicals, 2);
      AssertThrow(!physicals.empty(),
                  ExcMessage(where + ": the geometry has no Physical Surface "
                                     "(it gives the cells' material id)."));
      const auto generate = [&](const double size, const bool subdivide) {
        gmsh::model::mesh::clear();
        gmsh::option::setNumber("Mesh.MeshSizeMax", size);
        gmsh::option::setNumber("Mesh.Algorithm", 6); // Frontal-Delaunay
        gmsh::option::setNumber("Mesh.RecombineAll", 1);
        gmsh::option::setNumber("Mesh.RecombinationAlgorithm", 1); // Blossom
        gmsh::option::setNumber("Mesh.SubdivisionAlgorithm", subdivide ? 1 : 0);
        try
          {
            gmsh::model::mesh::generate(2);
          }
        catch (...)
          {
            AssertThrow(
              false, ExcMessage(internal::gmsh_error(where, "meshing failed")));
          }
        internal::gmsh_check_generated(2, where);
        std::vector<int>                      types;
        std::vector<std::vector<std::size_t>> tags, nodes;
        gmsh::model::mesh::getElements(types, tags, nodes, 2);
        for (const int t : types)
          if (t != 3) // 4-node quadrangle
            return false;
        return true;
      };
      if (!generate(element_size, false))
        AssertThrow(generate(2 * element_size, true),
                    ExcMessage(where + ": Gmsh left non-quad elements."));
      text = internal::gmsh_written_mesh();
    }
    tria.clear();
    std::istringstream in(text);
    GridIn<2>          grid_in(tria);
    grid_in.read_msh(in);
    check_mesh_validity(tria, where);
  }
} // namespace forma
