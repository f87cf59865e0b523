// Centrally symmetric cells: periodic_level_set_mesh with
// centrally_symmetric meshes the lower half and adds its copy rotated by pi;
// PeriodicHomogenization with inversion_symmetric makes the fluctuations
// odd. The cell: a tilted elliptical hole at the center (only the point
// symmetry, no mirror), a pair of holes on the sides y = 0, 1 and a pair
// inside, so contours cross the joint y = 1/2 and the sides.
//  - The mesh has the symmetry: every vertex's image is a vertex.
//  - Its area matches the whole-cell mesh's to O(h^2).
//  - On that mesh the odd constraints change C^H only by round-off and
//    leave about half the unknowns; against the whole-cell mesh C^H agrees
//    to discretization error.
//  - A floating disk across the joint is dropped and counted (the half
//    sees it touch its side).
//  - Odd constraints on a mesh without the symmetry, a symmetric mesh of a
//    level set without it or of one that is not periodic: refused with a
//    clear message.

#include <deal.II/grid/tria.h>

#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/periodic_homogenization.h>
#include <forma/mesh/level_set_mesh.h>

#include "../tests.h"

#include <algorithm>

using namespace dealii;
using namespace forma;

namespace
{
  // Distance to the nearest periodic image of c in the unit cell.
  Tensor<1, 2>
  offset(const Point<2> &x, const Point<2> &c)
  {
    Tensor<1, 2> d = x - c;
    for (unsigned int i = 0; i < 2; ++i)
      d[i] -= std::round(d[i]);
    return d;
  }

  // Material outside the holes (phi < 0), phi(1 - x) = phi(x).
  double
  cell(const Point<2> &x)
  {
    const double angle = 0.5;
    const double c = std::cos(angle), s = std::sin(angle);
    const auto   d = offset(x, Point<2>(0.5, 0.5));
    const double u = (c * d[0] + s * d[1]) / 0.25,
                 v = (-s * d[0] + c * d[1]) / 0.12;
    double phi     = 0.12 * (1 - std::sqrt(u * u + v * v));
    for (const Point<2> &h : {Point<2>(0.2, 0), Point<2>(0.8, 1)})
      phi = std::max(phi, 0.08 - offset(x, h).norm());
    for (const Point<2> &h : {Point<2>(0.25, 0.2), Point<2>(0.75, 0.8)})
      phi = std::max(phi, 0.07 - offset(x, h).norm());
    return phi;
  }

  struct Homogenized
  {
    SymmetricTensor<4, 2>   C;
    types::global_dof_index unknowns;
  };

  Homogenized
  homogenize(const Triangulation<2> &tria, const bool odd)
  {
    PeriodicHomogenization<2> cell(
      MPI_COMM_SELF, tria, Point<2>(1, 1), {}, 2, odd);
    const auto base = IsotropicModuli::from_young_poisson(1, 0.3).tensor();
    return {cell
              .homogenize([&](const Point<2> &, const types::material_id) {
                return base;
              })
              .C,
            cell.n_unknowns()};
  }

  // Every vertex has a vertex at its image 1 - x.
  bool
  symmetric(const Triangulation<2> &tria)
  {
    std::vector<std::pair<double, double>> points;
    for (const auto &v : tria.get_vertices())
      points.emplace_back(v[0], v[1]);
    std::sort(points.begin(), points.end());
    for (const auto &[x, y] : points)
      {
        const auto it    = std::lower_bound(points.begin(),
                                         points.end(),
                                         std::make_pair(1 - x - 1e-12, -1.));
        bool       found = false;
        for (auto j = it; j != points.end() && j->first < 1 - x + 1e-12; ++j)
          found |= std::abs(j->second - (1 - y)) < 1e-12;
        if (!found)
          return false;
      }
    return true;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  for (const double h : {0.05, 0.025})
    {
      LevelSetMeshParameters parameters;
      parameters.size          = 2 * h;
      parameters.boundary_size = h;
      Triangulation<2> whole, half;
      LevelSetMeshInfo whole_info, half_info;
      periodic_level_set_mesh(
        cell, Point<2>(1, 1), parameters, whole, MPI_COMM_SELF, &whole_info);
      parameters.centrally_symmetric = true;
      periodic_level_set_mesh(
        cell, Point<2>(1, 1), parameters, half, MPI_COMM_SELF, &half_info);

      const Homogenized full  = homogenize(whole, false);
      const Homogenized plain = homogenize(half, false);
      const Homogenized odd   = homogenize(half, true);
      const double ratio = static_cast<double>(odd.unknowns) / plain.unknowns;
      deallog << "h = " << h
              << ": symmetric mesh: " << (symmetric(half) ? "yes" : "NO")
              << ", area against the "
              << "whole cell's "
              << (std::abs(half_info.area - whole_info.area) < 0.6 * h * h ?
                    "< 0.6 h^2" :
                    "TOO LARGE")
              << ", odd constraints: |dC|/|C| "
              << ((odd.C - plain.C).norm() / plain.C.norm() < 1e-10 ?
                    "< 1e-10" :
                    "TOO LARGE")
              << " with unknowns x " << rounded(ratio, 2)
              << ", against the whole cell's C^H "
              << ((odd.C - full.C).norm() / full.C.norm() < 3e-3 ? "< 3e-3" :
                                                                   "TOO LARGE")
              << std::endl;
    }

  // Clear errors: the odd constraints on a mesh without the symmetry, a
  // symmetric half of a level set without it.
  expect_refusal(
    "odd constraints on an unsymmetric mesh",
    [] {
      Triangulation<2> tria;
      periodic_level_set_mesh(cell, Point<2>(1, 1), {}, tria);
      homogenize(tria, true);
    },
    "the mesh is not symmetric under the inversion");
  LevelSetMeshParameters symmetric_half;
  symmetric_half.centrally_symmetric = true;
  expect_refusal(
    "unsymmetric level set",
    [&] {
      Triangulation<2> tria;
      periodic_level_set_mesh(
        [](const Point<2> &x) {
          return 0.2 - offset(x, Point<2>(0.3, 0.4)).norm();
        },
        Point<2>(1, 1),
        symmetric_half,
        tria);
    },
    "the level set is not symmetric under the rotation by 180 degrees");

  // A disk floating in the central hole, across the joint.
  {
    const auto with_disk = [](const Point<2> &x) {
      const double r = x.distance(Point<2>(0.5, 0.5));
      return std::min(0.3 - r, r - 0.1);
    };
    Triangulation<2> tria;
    LevelSetMeshInfo info;
    periodic_level_set_mesh(
      with_disk, Point<2>(1, 1), symmetric_half, tria, MPI_COMM_SELF, &info);
    deallog << "disk across the joint: dropped " << info.dropped_islands
            << " floating piece, area = 1 - pi 0.3^2 to 2e-3: "
            << (std::abs(info.area - (1 - M_PI * 0.09)) < 2e-3 ? "yes" : "NO")
            << ", symmetric: " << (symmetric(tria) ? "yes" : "NO") << std::endl;
  }

  // Only periodic cells.
  expect_refusal(
    "not periodic",
    [&] {
      Triangulation<2> tria;
      level_set_mesh(
        [](const Point<2> &x) { return x.distance(Point<2>(0.5, 0.5)) - 0.2; },
        Point<2>(0, 0),
        Point<2>(1, 1),
        symmetric_half,
        tria);
    },
    "centrally_symmetric is for periodic cells");
}
