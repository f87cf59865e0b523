// Taylor test of the shape derivative dC^H/dp of rhombic structures
// (thesis ch. 4.5.1): for a design direction dp, the error
// |J(p + eps dp) - J(p) - eps dJ/dp . dp| must fall at rate 2, where J is
// a misfit of C^H to a target tensor (eq. 4.4) and J(p + eps dp) is
// evaluated on the cell mesh moved to the new design (same topology).
// Each parameter alone, and all together, on a 60 and a 90 degree cell.

#include <forma/rhombic/cell_model.h>

#include "../tests.h"

using namespace dealii;
using namespace forma;

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  rhombic::Setup setup;
  setup.base               = IsotropicModuli::from_young_poisson(1, 0);
  setup.mesh.size          = 0.1;
  setup.mesh.boundary_size = 0.05;
  const auto target        = IsotropicModuli::from_young_poisson(0.05, 0.2);
  // Squared Frobenius distance of the Voigt matrices.
  const VoigtMatrix T = to_voigt(target.tensor());
  const auto        J = [&](const SymmetricTensor<4, 2> &C) {
    const VoigtMatrix D = to_voigt(C) - T;
    return scalar_product(D, D);
  };
  const auto dJ = [&](const SymmetricTensor<4, 2> &C,
                      const SymmetricTensor<4, 2> &dC) {
    return 2 * scalar_product(to_voigt(C) - T, to_voigt(dC));
  };

  for (const double degrees : {60., 90.})
    {
      RhombicStructure s;
      s.alpha = degrees * M_PI / 180;
      s.p     = {{0.2, 0.15, 0.3, 0.7, 0.25, 0.08, 0.1, 0.08}};
      rhombic::CellModel model(s, setup, MPI_COMM_WORLD);
      const auto         C0   = model.sample().C;
      const auto         grad = model.gradient().C;
      for (unsigned int direction = 0; direction <= 8; ++direction)
        {
          // One parameter, or all at once (direction 8).
          std::array<double, 8> dp{};
          for (unsigned int i = 0; i < 8; ++i)
            if (direction == 8 || i == direction)
              dp[i] = (i % 2 == 0 ? 1. : -0.7) * (i >= 4 ? 0.3 : 1.);
          double slope = 0;
          for (unsigned int i = 0; i < 8; ++i)
            slope += dJ(C0, grad[i]) * dp[i];
          std::vector<double> eps, errors;
          for (const double e : {4e-4, 2e-4, 1e-4, 5e-5})
            {
              RhombicStructure t = s;
              for (unsigned int i = 0; i < 8; ++i)
                t.p[i] += e * dp[i];
              model.move_to(t);
              eps.push_back(e);
              errors.push_back(
                std::abs(J(model.sample().C) - J(C0) - e * slope));
            }
          model.move_to(s);
          const auto   rates = observed_rates(eps, errors);
          const double worst = *std::min_element(rates.begin(), rates.end());
          deallog << degrees << " degrees, "
                  << (direction == 8 ? std::string("all parameters") :
                                       "p" + std::to_string(direction + 1))
                  << ": rates " << (worst > 1.8 ? ">= 1.8" : "TOO LOW")
                  << std::endl;
        }
    }
}
