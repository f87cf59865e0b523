// Quad-to-rhombic mesh optimization of a Gmsh geometry with a given target
// cap (Minimum angle) and angle floor, on a quad mesh from a chosen Gmsh
// algorithm: one CSV line of shape statistics before and after. Used by
// rhombic_mesh_angles.sh.
//
//   rhombic_mesh_angles GEO SIZE MIN_ANGLE FLOOR [ALGORITHM RECOMBINATION]

#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/tria.h>

#include <forma/rhombic/quad_mesh_optimization.h>

#include <gmsh.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

using namespace dealii;
using namespace forma::rhombic;

namespace
{
  // Gmsh's quads of `geo` written as MSH 2.2 to `msh`; false if
  // triangles remain.
  bool
  gmsh_quads(const std::string &geo,
             const double       size,
             const int          algorithm,
             const int          recombination,
             const std::string &msh)
  {
    gmsh::initialize();
    // gmsh::finalize() also when Gmsh throws (a bad geometry).
    struct Finalize
    {
      ~Finalize()
      {
        gmsh::finalize();
      }
    } finalize;
    gmsh::option::setNumber("General.Terminal", 0);
    gmsh::open(geo);
    gmsh::option::setNumber("Mesh.MeshSizeMax", size);
    gmsh::option::setNumber("Mesh.Algorithm", algorithm);
    gmsh::option::setNumber("Mesh.RecombineAll", 1);
    gmsh::option::setNumber("Mesh.RecombinationAlgorithm", recombination);
    gmsh::model::mesh::generate(2);
    std::vector<int>                      types;
    std::vector<std::vector<std::size_t>> tags, nodes;
    gmsh::model::mesh::getElements(types, tags, nodes, 2);
    bool quads = true;
    for (const int t : types)
      quads = quads && t == 3;
    gmsh::option::setNumber("Mesh.MshFileVersion", 2.2);
    gmsh::write(msh);
    return quads;
  }
} // namespace

int
main(int argc, char **argv)
{
  if (argc != 5 && argc != 7)
    {
      std::cerr << "usage: rhombic_mesh_angles GEO SIZE MIN_ANGLE FLOOR "
                   "[ALGORITHM RECOMBINATION]\n";
      return 1;
    }
  try
    {
      constexpr double  degrees   = 180 / M_PI;
      const int         algorithm = argc == 7 ? std::stoi(argv[5]) : 6;
      const int         recombine = argc == 7 ? std::stoi(argv[6]) : 1;
      const std::string msh =
        (std::filesystem::temp_directory_path() /
         ("rhombic_mesh_angles_" + std::to_string(getpid()) + ".msh"))
          .string();
      if (!gmsh_quads(argv[1], std::stod(argv[2]), algorithm, recombine, msh))
        {
          std::cout << "triangles remain\n";
          return 0;
        }
      Triangulation<2> tria;
      GridIn<2>        in(tria);
      std::ifstream    f(msh);
      in.read_msh(f);
      std::filesystem::remove(msh);
      QuadMeshOptimizationParameters p;
      p.min_angle      = std::stod(argv[3]) / degrees;
      p.angle_floor    = std::stod(argv[4]) / degrees;
      const auto start = std::chrono::steady_clock::now();
      const auto r     = optimize_rhombic_mesh(tria, p);
      const std::chrono::duration<double> t =
        std::chrono::steady_clock::now() - start;
      std::printf("%u,%.1f,%.1f,%.3f,%.3f,%.1f,%.1f,%.3f,%.3f,%.1f,%.2f\n",
                  tria.n_active_cells(),
                  r.before.min_alpha * degrees,
                  r.before.mean_alpha * degrees,
                  r.before.mean_error,
                  r.before.max_error,
                  r.after.min_alpha * degrees,
                  r.after.mean_alpha * degrees,
                  r.after.mean_error,
                  r.after.max_error,
                  r.after.min_interior_angle * degrees,
                  t.count());
    }
  catch (const std::exception &e)
    {
      std::cerr << "rhombic_mesh_angles: " << e.what() << "\n";
      return 1;
    }
}
