// Adaptive refinement of a periodic cell (PeriodicHomogenization::refine):
// - a square cell with a rectangular hole (corners: singular stresses),
//   refined by the stress-jump indicators, 20% of the cells per cycle:
//   C^H_11 decreases in every cycle (nested spaces, C^H_aa the minimum of
//   the cell energy), stays above its limit, and reaches the error of a
//   uniform 64 x 64 grid with under a quarter of its unknowns;
// - on the refined grid (hanging nodes, also across the periodic sides) a
//   layered cell, whose exact fluctuation Q1 represents, still gives the
//   exact rank-one laminate tensor: the constraints are right;
// - an odd grid (the translation pin off the hanging vertices) and a 3D
//   grid (four children per face) refine and stay monotone; 3D layers on
//   the refined grid give the exact normal modulus.

#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/periodic_homogenization.h>

#include "../tests.h"

#include <cmath>

using namespace dealii;
using namespace forma;

namespace
{
  SymmetricTensor<4, 2>
  holed(const Point<2> &x, const types::material_id)
  {
    static const auto solid =
      IsotropicModuli::of_material(1.0, 0.3, PlaneModel::plane_strain);
    static const auto hole =
      IsotropicModuli::of_material(1e-4, 0.3, PlaneModel::plane_strain);
    const bool inside =
      std::abs(x[0] - 0.5) < 0.25 && std::abs(x[1] - 0.5) < 0.125;
    return inside ? hole.tensor() : solid.tensor();
  }

  PeriodicHomogenization<2>
  grid(const unsigned int n)
  {
    PeriodicHomogenization<2>::SolverParameters sp;
    sp.type = "direct";
    return PeriodicHomogenization<2>(MPI_COMM_WORLD,
                                     Point<2>(1, 1),
                                     {{n, n}},
                                     sp);
  }

  double
  c11(PeriodicHomogenization<2> &cell)
  {
    return to_voigt(cell.homogenize(holed).C)[0][0];
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  auto         uniform          = grid(64);
  const double uniform_c11      = c11(uniform),
               uniform_unknowns = uniform.n_unknowns();

  auto                                   cell = grid(8);
  std::vector<std::pair<double, double>> history{
    {cell.n_unknowns(), c11(cell)}}; // (unknowns, C11)
  for (unsigned int k = 1; k <= 12; ++k)
    {
      cell.refine(holed, 0.2);
      history.emplace_back(cell.n_unknowns(), c11(cell));
    }
  // The limit: the last value, less the geometric tail of its decrements.
  const unsigned int n    = history.size() - 1;
  const double       d1   = history[n - 1].second - history[n].second,
               d2         = history[n - 2].second - history[n - 1].second;
  const double limit      = history[n].second - d1 * (d1 / d2) / (1 - d1 / d2);
  bool         decreasing = true;
  double       reached_at = 0;
  for (unsigned int k = 1; k <= n; ++k)
    decreasing &= history[k].second < history[k - 1].second;
  for (const auto &[unknowns, c] : history)
    if (reached_at == 0 && c - limit <= uniform_c11 - limit)
      reached_at = unknowns;
  deallog << "C11: limit " << rounded(limit, 4) << ", uniform 64 x 64 "
          << rounded(uniform_c11, 4) << std::endl;
  check("C11 decreases in every one of 12 cycles", decreasing);
  check("the last cycle is above the limit", history[n].second > limit);
  check("the uniform 64 x 64 error reached with under a quarter of its "
        "unknowns",
        reached_at > 0 && reached_at < 0.25 * uniform_unknowns);

  const auto a =
    IsotropicModuli::of_material(1.0, 0.3, PlaneModel::plane_strain);
  const auto b =
    IsotropicModuli::of_material(0.05, -0.2, PlaneModel::plane_strain);
  const auto layered =
    cell.homogenize([&](const Point<2> &x, const types::material_id) {
      return x[1] < 0.375 ? a.tensor() : b.tensor();
    });
  const auto exact = rank_one_laminate(a.tensor(), b.tensor(), 0.375, 0);
  deallog << "layered cell on the refined grid: |C - C_exact| / |C| "
          << ((layered.C - exact).norm() / exact.norm() < 1e-8 ? "< 1e-8" :
                                                                 "TOO LARGE")
          << std::endl;

  // An odd grid: the center is a cell center, and the vertex nearest it,
  // which pins the translations, must not be a hanging one. The hole lies
  // on grid lines, so that refining leaves the material as it is.
  {
    const auto on_grid = [](const Point<2> &x, const types::material_id id) {
      return holed(Point<2>(0.5 + (x[0] - 0.5) * 0.25 / (1.5 / 9),
                            0.5 + (x[1] - 0.5) * 0.125 / (1.5 / 7)),
                   id);
    };
    PeriodicHomogenization<2>::SolverParameters sp;
    sp.type = "direct";
    PeriodicHomogenization<2> odd(MPI_COMM_WORLD, Point<2>(1, 1), {{9, 7}}, sp);
    double previous = to_voigt(odd.homogenize(on_grid).C)[0][0];
    bool   ok       = true;
    for (unsigned int k = 0; k < 4; ++k)
      {
        odd.refine(on_grid, 0.3);
        const double c = to_voigt(odd.homogenize(on_grid).C)[0][0];
        ok &= std::isfinite(c) && c < previous;
        previous = c;
      }
    check("9 x 7 grid: C11 finite and decreasing in 4 cycles", ok);
  }

  // 3D: four children per face, hanging faces across the periodic sides.
  {
    PeriodicHomogenization<3>::SolverParameters sp;
    sp.type = "direct";
    PeriodicHomogenization<3> cube(MPI_COMM_WORLD,
                                   Point<3>(1, 1, 1),
                                   {{4, 4, 4}},
                                   sp);
    const auto                iso = [](const double E, const double nu) {
      const double l = E * nu / ((1 + nu) * (1 - 2 * nu)), m = E / (2 + 2 * nu);
      SymmetricTensor<4, 3> C;
      for (unsigned int i = 0; i < 3; ++i)
        for (unsigned int j = 0; j < 3; ++j)
          {
            C[i][i][j][j] += l;
            C[i][j][i][j] += m;
          }
      return C;
    };
    const auto hole3 = [&](const Point<3> &x, const types::material_id) {
      return std::abs(x[0] - 0.5) < 0.25 && std::abs(x[1] - 0.5) < 0.25 ?
               iso(1e-4, 0.3) :
               iso(1, 0.3);
    };
    double previous = cube.homogenize(hole3).C[0][0][0][0];
    bool   ok       = true;
    for (unsigned int k = 0; k < 2; ++k)
      {
        cube.refine(hole3, 0.2);
        const double c = cube.homogenize(hole3).C[0][0][0][0];
        ok &= c < previous;
        previous = c;
      }
    check("3D: C1111 decreasing in 2 cycles", ok);
    // Layers normal to z on the refined grid: the harmonic mean of the
    // normal moduli (the 1D problem), exactly.
    const auto soft = iso(0.1, 0.), hard = iso(1., 0.25);
    const auto layers =
      cube.homogenize([&](const Point<3> &x, const types::material_id) {
        return x[2] < 0.5 ? hard : soft;
      });
    const double exact_zzzz =
      1. / (0.5 / hard[2][2][2][2] + 0.5 / soft[2][2][2][2]);
    deallog << "3D layered cell on the refined grid: C_zzzz "
            << (std::abs(layers.C[2][2][2][2] / exact_zzzz - 1) < 1e-8 ?
                  "exact to 1e-8" :
                  "WRONG")
            << std::endl;
  }
}
