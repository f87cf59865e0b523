// periodic_level_set_mesh: conforming periodic meshes of a level set's
// material.
//  - A circular hole: the meshed area matches 1 - pi r^2 to O(h^2) (the
//    boundary vertices lie on the circle; an inscribed polygon with edges
//    h misses about (pi / 6) h^2).
//  - The same hole centered on a corner of the cell (it crosses all four
//    periodic sides): the same periodic structure, so the same C^H up to
//    discretization error, and the mesh's sides match (the homogenization
//    accepts it).
//  - A floating island inside the hole is dropped; material that misses
//    the sides is refused with a clear message.
//  - Not periodic: a hole 5e-4 from the edge of a disk, resampled with
//    elements of 0.05, makes crossing contours: an error that says where,
//    or with max_thickenings a mesh thickened next to the wall only;
//    largest_piece_only keeps the larger of two distant disks.
//  - Each mesh opens a Gmsh session; PATH and PYTHONPATH are as before
//    (Gmsh 4.8 appends to them on every initialize: quadratic memory in a
//    long build map).

#include <deal.II/grid/tria.h>

#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/periodic_homogenization.h>
#include <forma/mesh/level_set_mesh.h>

#include "../tests.h"

#include <cstdio>
#include <cstdlib>
#include <string>

using namespace dealii;
using namespace forma;

namespace
{
  // Distance to the periodic images of a circle, negative outside it
  // (the hole) = material.
  std::function<double(const Point<2> &)>
  hole(const Point<2> &center, const double r)
  {
    return [center, r](const Point<2> &x) {
      double d = 1e300;
      for (int i = -1; i <= 1; ++i)
        for (int j = -1; j <= 1; ++j)
          d = std::min(d, x.distance(center + Tensor<1, 2>({1. * i, 1. * j})));
      return r - d;
    };
  }

  // level_set_mesh of phi on the unit box (not periodic).
  LevelSetMeshInfo
  mesh_unit_box(const std::function<double(const Point<2> &)> &phi,
                const LevelSetMeshParameters                  &parameters,
                Triangulation<2>                              &tria)
  {
    LevelSetMeshInfo info;
    level_set_mesh(phi,
                   Point<2>(0, 0),
                   Point<2>(1, 1),
                   parameters,
                   tria,
                   MPI_COMM_WORLD,
                   &info);
    return info;
  }

  SymmetricTensor<4, 2>
  homogenize(const std::function<double(const Point<2> &)> &phi,
             const LevelSetMeshParameters                  &parameters,
             LevelSetMeshInfo                              &info)
  {
    Triangulation<2> tria;
    periodic_level_set_mesh(
      phi, Point<2>(1, 1), parameters, tria, MPI_COMM_WORLD, &info);
    PeriodicHomogenization<2> cell(MPI_COMM_WORLD, tria, Point<2>(1, 1), {}, 2);
    const auto base = IsotropicModuli::from_young_poisson(1, 0.3).tensor();
    return cell
      .homogenize(
        [&](const Point<2> &, const types::material_id) { return base; })
      .C;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const auto environment = []() {
    std::string text;
    for (const char *name : {"PATH", "PYTHONPATH"})
      text += std::string(name) + "=" +
              (std::getenv(name) ? std::getenv(name) : "(unset)") + "\n";
    return text;
  };
  const std::string environment_before = environment();
  const double      r = 0.3, exact = 1 - M_PI * r * r;

  std::vector<double>   sizes, errors;
  SymmetricTensor<4, 2> C_center, C_corner;
  for (const double h : {0.1, 0.05, 0.025})
    {
      LevelSetMeshParameters parameters;
      parameters.grid          = 64;
      parameters.size          = h;
      parameters.boundary_size = h;
      LevelSetMeshInfo info;
      C_center = homogenize(hole(Point<2>(0.5, 0.5), r), parameters, info);
      sizes.push_back(h);
      errors.push_back(std::abs(info.area - exact));
      LevelSetMeshInfo corner_info;
      C_corner = homogenize(hole(Point<2>(0, 0), r), parameters, corner_info);
      deallog << "h = " << h << ": area error "
              << (errors.back() < 0.6 * h * h ? "< 0.6 h^2" : "TOO LARGE")
              << ", hole on the corner: area error "
              << (std::abs(corner_info.area - exact) < 0.6 * h * h ?
                    "< 0.6 h^2" :
                    "TOO LARGE")
              << ", |C_corner - C_center|/|C| "
              << ((C_corner - C_center).norm() / C_center.norm() < 3e-3 ?
                    "< 3e-3" :
                    "TOO LARGE")
              << std::endl;
    }
  const auto rates = observed_rates(sizes, errors);
  deallog << "area error rate " << (rates.back() > 1.7 ? ">= 1.7" : "TOO LOW")
          << std::endl;
  const auto fit = isotropic_fit(C_center);
  deallog << "square array of holes, r = 0.3: E = " << rounded(fit.E, 3)
          << ", nu = " << rounded(fit.nu, 3)
          << ", C00 = C11: " << (anisotropy(C_center).a1 < 1e-3 ? "yes" : "NO")
          << std::endl;

  // An island floating in the hole.
  {
    LevelSetMeshParameters parameters;
    parameters.grid        = 64;
    const auto with_island = [&](const Point<2> &x) {
      const double island = x.distance(Point<2>(0.5, 0.5)) - 0.1;
      return std::min(hole(Point<2>(0.5, 0.5), r)(x), island);
    };
    Triangulation<2> tria;
    LevelSetMeshInfo info;
    periodic_level_set_mesh(
      with_island, Point<2>(1, 1), parameters, tria, MPI_COMM_WORLD, &info);
    deallog << "island: dropped " << info.dropped_islands
            << " floating piece, area = 1 - pi r^2 to 2e-3: "
            << (std::abs(info.area - exact) < 2e-3) << std::endl;
  }
  // Material that does not reach the sides.
  try
    {
      Triangulation<2> tria;
      periodic_level_set_mesh(
        [](const Point<2> &x) { return x.distance(Point<2>(0.5, 0.5)) - 0.2; },
        Point<2>(1, 1),
        LevelSetMeshParameters(),
        tria,
        MPI_COMM_WORLD);
      deallog << "a lone disk was meshed: WRONG" << std::endl;
    }
  catch (const std::exception &e)
    {
      const std::string what = e.what();
      deallog << "a lone disk is refused: "
              << (what.find("cell: the material does not reach the sides") !=
                      std::string::npos ?
                    "the material does not reach the sides" :
                    what)
              << std::endl;
    }

  // A disk of radius 0.4 with a hole of radius 0.2 whose edge comes to
  // w = 5e-4 of the disk's (a grid fine enough to see the wall, boundary
  // elements too long for it: the chords cross).
  {
    const double   R = 0.4, r = 0.2, w = 5e-4;
    const Point<2> c(0.5, 0.5), hole_center = c + Tensor<1, 2>({R - r - w, 0});
    const auto     disk_with_hole = [&](const Point<2> &x) {
      return std::max(x.distance(c) - R, r - x.distance(hole_center));
    };
    LevelSetMeshParameters parameters;
    parameters.grid          = 4096;
    parameters.size          = 0.05;
    parameters.boundary_size = 0.05;
    try
      {
        Triangulation<2> tria;
        mesh_unit_box(disk_with_hole, parameters, tria);
        deallog << "thin wall: meshed without thickening: WRONG" << std::endl;
      }
    catch (const std::exception &e)
      {
        // The message as one line (deal.II wraps it).
        std::string what;
        for (const char ch : std::string(e.what()))
          if (ch != '\n' && !(ch == ' ' && !what.empty() && what.back() == ' '))
            what += ch;
        const auto at = what.find("crosses the material's boundary near (");
        double     x = 0, y = 0;
        if (at != std::string::npos)
          std::sscanf(what.c_str() + what.find('(', at), "(%lf, %lf)", &x, &y);
        deallog << "thin wall: "
                << (std::abs(x - 0.9) < 0.03 && std::abs(y - 0.5) < 0.03 ?
                      "error near the wall (0.9, 0.5)" :
                      what)
                << std::endl;
      }
    parameters.max_thickenings = 5;
    Triangulation<2>       tria;
    const LevelSetMeshInfo info =
      mesh_unit_box(disk_with_hole, parameters, tria);
    // Boundary vertices: on the given zero set farther than 5 b from the
    // wall, moved out (phi > 0) next to it.
    const Point<2> wall(c[0] + R, c[1]);
    double         far = 0, near = 0;
    for (const auto &cell : tria.active_cell_iterators())
      for (const auto &face : cell->face_iterators())
        if (face->at_boundary())
          for (const unsigned int v : face->vertex_indices())
            {
              const Point<2> &x = face->vertex(v);
              if (x.distance(wall) > 5 * parameters.boundary_size)
                far = std::max(far, std::abs(disk_with_hole(x)));
              else
                near = std::max(near, disk_with_hole(x));
            }
    deallog << "thin wall, thickened " << info.thickenings
            << " time(s): " << info.boundary_loops
            << " boundary loops; boundary beyond 5 b of the wall on the "
            << "given zero set: " << (far < 1e-8 ? "yes" : "NO")
            << ", moved out by up to b next to it: "
            << (near > 0.1 * parameters.boundary_size &&
                    near <= 1.01 * parameters.boundary_size * info.thickenings ?
                  "yes" :
                  "NO")
            << std::endl;
  }
  {
    LevelSetMeshParameters parameters;
    parameters.largest_piece_only = true;
    Triangulation<2> tria;
    // The larger disk on the right: traced second.
    const LevelSetMeshInfo info = mesh_unit_box(
      [](const Point<2> &x) {
        return std::min(x.distance(Point<2>(0.2, 0.5)) - 0.1,
                        x.distance(Point<2>(0.7, 0.5)) - 0.2);
      },
      parameters,
      tria);
    deallog << "largest piece only: dropped " << info.dropped_islands
            << ", area = pi 0.2^2 to 2e-3: "
            << (std::abs(info.area - M_PI * 0.04) < 2e-3) << std::endl;
  }
  deallog << "PATH and PYTHONPATH unchanged by the Gmsh sessions: "
          << (environment() == environment_before ? "yes" : "NO") << std::endl;
}
