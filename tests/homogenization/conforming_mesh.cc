// The conforming-mesh path of the homogenization: periodic Gmsh meshes of
// polygon phases (periodic_phase_mesh) on the sqrt(3) x 1 cell.
//  - Layers along x and along y, and layers inclined at -30 degrees (along the
//  cell's diagonal, periodic on
//    the box) on P1 and P2 triangles: the interfaces are mesh edges, so
//    the exact fluctuation is in the space and C^H must equal the rank-one
//    laminate to round-off.
//  - A Triangle structure: the meshed volume fraction equals eq. 5.11 and
//    the result is isotropic and inside the HS bounds.

#include <deal.II/grid/tria.h>

#include <forma/homogenization/bounds.h>
#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/periodic_homogenization.h>
#include <forma/mesh/periodic_phase_mesh.h>
#include <forma/microstructure/hexagonal_laminate.h>
#include <forma/microstructure/pixel_material.h>

#include "../tests.h"

using namespace dealii;
using namespace forma;

namespace
{
  const double W = HexagonalLaminate::width, H = HexagonalLaminate::height;

  using Polygons = std::vector<std::pair<std::vector<Point<2>>, unsigned int>>;

  // Layers of material a (fraction 0.4, given by `strips`) and b at
  // `layer_angle`, meshed by periodic_phase_mesh: C^H on P1 and P2
  // triangles against the exact rank-one laminate.
  void
  check_layers(const std::string &name,
               Polygons           strips,
               const double       layer_angle)
  {
    const auto a =
      IsotropicModuli::of_material(1.0, 0.3, PlaneModel::plane_stress);
    const auto b =
      IsotropicModuli::of_material(0.02, 0.1, PlaneModel::plane_stress);
    for (auto &s : strips)
      if (area(s.first) < 0)
        std::reverse(s.first.begin(), s.first.end());
    Triangulation<2> mesh;
    periodic_phase_mesh(strips, Point<2>(W, H), 0.15, mesh);
    double fraction = 0;
    for (const auto &cell : mesh.active_cell_iterators())
      fraction += (cell->material_id() == 1) * cell->measure();
    deallog << name << ": meshed fraction of a " << rounded(fraction / (W * H))
            << std::endl;
    const auto exact =
      rank_one_laminate(a.tensor(), b.tensor(), 0.4, layer_angle);
    for (const unsigned int degree : {1u, 2u})
      {
        PeriodicHomogenization<2> cell(MPI_COMM_WORLD, mesh, {}, degree);
        const auto                C =
          cell
            .homogenize([&](const Point<2> &, const types::material_id id) {
              return id == 1 ? a.tensor() : b.tensor();
            })
            .C;
        const double error = (C - exact).norm() / exact.norm();
        deallog << "  P" << degree << ": |C - C_laminate| / |C| "
                << (error < 1e-9 ? "< 1e-9" : "TOO LARGE") << std::endl;
      }
  }

  void
  layers()
  {
    // Along x and y: one rectangle reaching out of the box.
    check_layers("layers along x",
                 {{{Point<2>(-1, 0.2),
                    Point<2>(3, 0.2),
                    Point<2>(3, 0.6),
                    Point<2>(-1, 0.6)},
                   0}},
                 0);
    check_layers("layers along y",
                 {{{Point<2>(0.2, -1),
                    Point<2>(0.2 + 0.4 * W, -1),
                    Point<2>(0.2 + 0.4 * W, 2),
                    Point<2>(0.2, 2)},
                   0}},
                 numbers::PI / 2);
    // Along the cell's diagonal (-30 degrees): material a where
    // frac(x / W + y / H) < 0.4, strips of the (x / W, y / H) plane passed
    // unclipped with their periodic image.
    Polygons strips;
    for (const double k : {0., 1.})
      strips.push_back({{Point<2>(W * (k + 1), -H),
                         Point<2>(W * (k + 0.4 + 1), -H),
                         Point<2>(W * (k + 0.4 - 2), 2 * H),
                         Point<2>(W * (k - 2), 2 * H)},
                        0});
    check_layers("inclined layers", strips, -numbers::PI / 6);
  }

  void
  triangle_structure()
  {
    HexagonalLaminate s;
    s.family = HexagonalLaminate::Family::triangle;
    s.p1 = 0.7, s.p2 = 0.5, s.p3 = 0.5, s.p4 = 0.6;
    const auto base =
      IsotropicModuli::of_material(1, 0, PlaneModel::plane_stress);
    const auto weak =
      IsotropicModuli::from_bulk_shear(1e-6 * base.kappa, 1e-6 * base.mu);
    std::vector<std::pair<std::vector<Point<2>>, unsigned int>> polygons;
    for (const auto &p : s.polygons())
      polygons.push_back(p);
    Triangulation<2> mesh;
    periodic_phase_mesh(polygons, Point<2>(W, H), 0.03, mesh);
    double phi = 0;
    for (const auto &cell : mesh.active_cell_iterators())
      phi += (cell->material_id() == 1) * cell->measure();
    phi /= W * H;
    PeriodicHomogenization<2> cell(MPI_COMM_WORLD, mesh, {}, 2);
    const auto                C =
      cell
        .homogenize([&](const Point<2> &, const types::material_id id) {
          return id == 1 ? base.tensor() : weak.tensor();
        })
        .C;
    const auto fit = isotropic_fit(C);
    const auto an  = anisotropy(C);
    deallog
      << "triangle p1 = 0.7, p2 = 0.5, p3 = 0.5, p4 = 0.6: phi - eq. 5.11 "
      << (std::abs(phi - s.volume_fraction_formula()) < 1e-10 ? "< 1e-10" :
                                                                "LARGE")
      << ", E = " << rounded(fit.E, 3) << ", nu = " << rounded(fit.nu, 3)
      << ", isotropic (|a1|, |a2| < 5e-3): "
      << (std::abs(an.a1) < 5e-3 && std::abs(an.a2) < 5e-3 ? "yes" : "NO")
      << ", inside HS: "
      << (hashin_shtrikman(base, weak, phi).violation(fit) <= 0 ? "yes" : "NO")
      << std::endl;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    initlog();
  layers();
  triangle_structure();
}
