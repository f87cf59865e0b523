#ifndef forma_homogenization_coverage_h
#define forma_homogenization_coverage_h

#include <forma/homogenization/elastic_tensor.h>

#include <array>
#include <vector>

namespace forma
{
  /**
   * Coverage of the (E, nu) plane by a family of isotropic structures
   * (thesis ch. 5.5). Samples are (nu, E / E_b) pairs of 2D moduli.
   */
  struct CoverageCoefficients
  {
    double       nu_right = 0, nu_left = 0;       ///< extreme nu achieved
    double       limit_right = 0, limit_left = 0; ///< HS at phi = 1
    double       delta_right = 0, delta_left = 0; ///< Delta_R, Delta_L
    unsigned int n_in_band = 0;
  };

  /**
   * Delta_R and Delta_L: the highest and lowest nu achieved by samples with
   * E / E_b within `band` of `level` (0.5 in the thesis), divided by the
   * nu of the phi = 1 Hashin-Shtrikman bound at that E (+-0.5 for nu_b = 0).
   */
  CoverageCoefficients
  coverage_coefficients(const std::vector<std::array<double, 2>> &samples,
                        const IsotropicModuli                    &base,
                        const double                              level = 0.5,
                        const double                              band  = 0.02);

  /**
   * The upper envelope max E / E_b of the samples in `n_bins` bins of nu
   * over [nu_min, nu_max] (bins without samples are skipped).
   */
  std::vector<std::array<double, 2>>
  upper_envelope(const std::vector<std::array<double, 2>> &samples,
                 const double                              nu_min,
                 const double                              nu_max,
                 const unsigned int                        n_bins);

  /**
   * Least-squares fit of eq. 5.10,
   *   E(nu) = 1 + (1 + c1 - c2 + c3) nu + c1 nu^2 + c2 nu^3 + c3 nu^4,
   * to (nu, E / E_b) points; the form passes through (0, 1) and (-1, 0), so
   * it describes the achieved boundary on the negative-nu side for a base
   * with nu_b = 0. Returns {c1, c2, c3}.
   */
  std::array<double, 3>
  fit_boundary_polynomial(const std::vector<std::array<double, 2>> &points);
} // namespace forma

#endif
