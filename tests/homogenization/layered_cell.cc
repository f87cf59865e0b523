// Analytic check of the periodic homogenization: a cell of two layers of
// different isotropic materials (grid-aligned, so the exact fluctuation is
// piecewise linear and Q1 represents it) must give the exact rank-one
// laminate tensor, for layers along x and along y, plane stress and plane
// strain, direct and AMG solvers; C^H must be symmetric and positive
// definite. A 3D layered cell checks the same against a 1D computation.

#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/periodic_homogenization.h>

#include "../tests.h"

using namespace dealii;
using namespace forma;

namespace
{
  double
  relative_error(const SymmetricTensor<4, 2> &A, const SymmetricTensor<4, 2> &B)
  {
    return (A - B).norm() / B.norm();
  }

  void
  check_2d(const PlaneModel model, const std::string &solver)
  {
    const auto   a     = IsotropicModuli::of_material(1.0, 0.3, model);
    const auto   b     = IsotropicModuli::of_material(0.05, -0.2, model);
    const double theta = 0.375; // 3 of 8 cell rows are material a
    PeriodicHomogenization<2>::SolverParameters sp;
    sp.type = solver;
    PeriodicHomogenization<2> cell(MPI_COMM_WORLD,
                                   Point<2>(2.0, 1.0),
                                   {{16, 8}},
                                   sp);
    for (const unsigned int layers_along : {0u, 1u})
      {
        // Material a where the coordinate across the layers is < theta.
        const auto result =
          cell.homogenize([&](const Point<2> &x, const types::material_id) {
            const double across = layers_along == 0 ? x[1] : x[0] / 2.0;
            return across < theta ? a.tensor() : b.tensor();
          });
        const auto        exact = rank_one_laminate(a.tensor(),
                                             b.tensor(),
                                             theta,
                                             layers_along == 0 ? 0 : M_PI / 2);
        const VoigtMatrix V     = to_voigt(result.C);
        deallog << (model == PlaneModel::plane_stress ? "plane stress" :
                                                        "plane strain")
                << ", " << result.solver << ", layers along "
                << (layers_along == 0 ? "x" : "y") << ": |C - C_exact|/|C| "
                << (relative_error(result.C, exact) < 1e-8 ? "< 1e-8" :
                                                             "TOO LARGE")
                << ", asymmetry "
                << (std::abs(V[0][1] - V[1][0]) + std::abs(V[0][2] - V[2][0]) <
                        1e-12 ?
                      "0" :
                      "NONZERO")
                << ", smallest eigenvalue "
                << rounded(smallest_eigenvalue(result.C)) << std::endl;
        // Entries below 1e-12 |C| are round-off: print them as 0.
        auto entry = [&](const unsigned int i, const unsigned int j) {
          return std::abs(V[i][j]) < 1e-12 * V.norm() ? 0. : rounded(V[i][j]);
        };
        deallog << "  C_voigt = [" << entry(0, 0) << ' ' << entry(0, 1) << ' '
                << entry(0, 2) << "; " << entry(1, 1) << ' ' << entry(1, 2)
                << "; " << entry(2, 2) << "]" << std::endl;
      }
  }

  void
  check_3d()
  {
    // Layers normal to z: the exact tensor from the 1D problem,
    // C^H_zz..: harmonic means of the "normal" moduli.
    const double E[2] = {1.0, 0.1}, nu[2] = {0.25, 0.0}, theta = 0.5;
    auto         iso = [](const double E, const double nu) {
      const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)),
                   mu     = E / (2 * (1 + nu));
      const SymmetricTensor<2, 3> I = unit_symmetric_tensor<3>();
      return SymmetricTensor<4, 3>(lambda * outer_product(I, I) +
                                   2 * mu * identity_tensor<3>());
    };
    PeriodicHomogenization<3>::SolverParameters sp;
    PeriodicHomogenization<3>                   cell(MPI_COMM_WORLD,
                                   Point<3>(1, 1, 1),
                                   {{2, 2, 4}},
                                   sp);
    const auto                                  result =
      cell.homogenize([&](const Point<3> &x, const types::material_id) {
        return x[2] < theta ? iso(E[0], nu[0]) : iso(E[1], nu[1]);
      });
    // C_zzzz = 1 / <1 / (lambda + 2 mu)>, C_xzxz = 1 / <1 / mu>
    double inv_p = 0, inv_mu = 0;
    for (unsigned int k = 0; k < 2; ++k)
      {
        const double lambda = E[k] * nu[k] / ((1 + nu[k]) * (1 - 2 * nu[k])),
                     mu     = E[k] / (2 * (1 + nu[k]));
        inv_p += 0.5 / (lambda + 2 * mu);
        inv_mu += 0.5 / mu;
      }
    deallog << "3d layers: C_zzzz error "
            << (std::abs(result.C[2][2][2][2] - 1 / inv_p) < 1e-10 ? "< 1e-10" :
                                                                     "LARGE")
            << ", C_xzxz error "
            << (std::abs(result.C[0][2][0][2] - 1 / inv_mu) < 1e-10 ?
                  "< 1e-10" :
                  "LARGE")
            << std::endl;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    initlog();
  check_2d(PlaneModel::plane_stress, "direct");
  check_2d(PlaneModel::plane_strain, "direct");
  check_2d(PlaneModel::plane_stress, "cg-amg");
  check_3d();
}
