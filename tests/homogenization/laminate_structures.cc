// Triangle and Hexagon structures (thesis ch. 5.3-5.4): the rasterized
// volume fraction equals eq. 5.11/5.12 (the rasterization is exact in
// area), the homogenized tensors are isotropic up to the grid's
// discretization (|a1|, |a2| small; the geometry has exact pi/3 symmetry),
// symmetric positive definite, and inside the Hashin-Shtrikman bounds.

#include <forma/homogenization/bounds.h>
#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/periodic_homogenization.h>
#include <forma/microstructure/hexagonal_laminate.h>

#include "../tests.h"

using namespace dealii;
using namespace forma;

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const unsigned int ny = 74, nx = 128;
  const auto         base       = IsotropicModuli::from_young_poisson(1, 0);
  const double       weak_ratio = 1e-6;
  const auto         weak = IsotropicModuli::from_young_poisson(weak_ratio, 0);
  PeriodicHomogenization<2>::SolverParameters sp;
  PeriodicHomogenization<2>                   cell(MPI_COMM_SELF,
                                 Point<2>(HexagonalLaminate::width,
                                          HexagonalLaminate::height),
                                 {{nx, ny}},
                                 sp);

  std::vector<HexagonalLaminate> structures(6);
  structures[0].family = HexagonalLaminate::Family::hexagon;
  structures[0].p1 = 0.75, structures[0].p2 = 0.1, structures[0].p3 = 1,
  structures[0].p4     = 0.77;
  structures[1].family = HexagonalLaminate::Family::triangle;
  structures[1].p1 = 0.73, structures[1].p2 = 0.2, structures[1].p3 = 0.7,
  structures[1].p4     = 0.805;
  structures[2].family = HexagonalLaminate::Family::hexagon;
  structures[2].p1 = 0.6, structures[2].p2 = 0.5, structures[2].p3 = 0.3,
  structures[2].p4     = 0.5;
  structures[3].family = HexagonalLaminate::Family::triangle;
  structures[3].p1 = 0.5, structures[3].p2 = 0, structures[3].p3 = 0.25,
  structures[3].p4     = 0.6;
  structures[4].family = HexagonalLaminate::Family::hexagon;
  structures[4].limit = true, structures[4].p1 = 0.8, structures[4].theta = 0.9,
  structures[4].alpha  = 0;
  structures[5].family = HexagonalLaminate::Family::triangle;
  structures[5].limit = true, structures[5].p1 = 0.85,
  structures[5].theta = 0.95, structures[5].alpha = 0.0;

  for (const auto &s : structures)
    {
      const PhaseRaster                  raster       = s.rasterize(nx, ny);
      std::vector<SymmetricTensor<4, 2>> phase_tensor = {base.tensor()};
      for (const double axis : s.joint_axis_angles())
        phase_tensor.push_back(rank_one_laminate(
          base.tensor(), weak.tensor(), s.theta, axis + s.lamination_angle()));
      double measured = raster.mean(0);
      for (unsigned int k = 1; k < raster.n_phases; ++k)
        measured += s.theta * raster.mean(k);

      const auto result =
        cell.homogenize([&](const Point<2> &x, const types::material_id) {
          const auto [i, j] = raster.cell_of(x);
          SymmetricTensor<4, 2> C;
          double                rest = 1;
          for (unsigned int k = 0; k < raster.n_phases; ++k)
            {
              C += raster.fraction(i, j, k) * phase_tensor[k];
              rest -= raster.fraction(i, j, k);
            }
          return SymmetricTensor<4, 2>(C + std::max(0., rest) * weak.tensor());
        });
      const auto       fit = isotropic_fit(result.C);
      const Anisotropy a   = anisotropy(result.C);
      const auto       hs  = hashin_shtrikman(base, weak, measured);
      deallog << s.family_name() << (s.limit ? " limit" : "") << ": phi "
              << rounded(measured, 6) << " eq. 5.11 "
              << rounded(s.volume_fraction_formula(), 6) << ", E "
              << rounded(fit.E, 3) << " nu " << rounded(fit.nu, 3)
              << ", isotropic (a1, a2 < 0.03): " << (a.a1 < 0.03 && a.a2 < 0.03)
              << ", positive definite: " << (smallest_eigenvalue(result.C) > 0)
              << ", inside HS: " << (hs.violation(fit) <= 0) << std::endl;
      deallog << "  a1 " << rounded(a.a1, 2) << ", a2 " << rounded(a.a2, 2)
              << std::endl;
    }
}
