#include <forma/laminate/study.h>

namespace forma
{
  namespace laminate
  {
    using namespace dealii;

    SampleGradient
    evaluate_gradient(const PeriodicHomogenization<2> &cell,
                      const HexagonalLaminate         &structure,
                      const Setup                     &setup,
                      const unsigned int               nx,
                      const unsigned int               ny,
                      const Sample                    &sample)
    {
      constexpr unsigned int      n = HexagonalLaminate::n_continuous;
      const PixelMaterialGradient pixels(
        structure, setup.base, setup.weak, setup.gray, nx, ny);
      const auto dC = cell.material_gradient(
        [&](const Point<2> &x, const types::material_id) {
          const auto &d = pixels(x);
          return std::vector<SymmetricTensor<4, 2>>(d.begin(), d.end());
        },
        n);
      // The fit's kappa and mu are linear in C; E = 4 kappa mu / (kappa +
      // mu) and nu = (kappa - mu) / (kappa + mu).
      const double   kappa = sample.fit.kappa, mu = sample.fit.mu;
      const double   s2 = (kappa + mu) * (kappa + mu);
      SampleGradient g;
      for (unsigned int m = 0; m < n; ++m)
        {
          const IsotropicModuli d = isotropic_fit(dC[m]);
          g.C[m]                  = dC[m];
          g.E[m]  = 4 * (mu * mu * d.kappa + kappa * kappa * d.mu) / s2;
          g.nu[m] = 2 * (mu * d.kappa - kappa * d.mu) / s2;
        }
      return g;
    }
  } // namespace laminate
} // namespace forma
