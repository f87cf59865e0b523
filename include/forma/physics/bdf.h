#ifndef forma_physics_bdf_h
#define forma_physics_bdf_h

#include <vector>

namespace forma
{
  /**
   * BDF coefficients in the thesis's form (eq. 3.12):
   *   u^i + sum_{j=1..m} alpha_j u^{i-j} = beta dt udot^i.
   * Steps i < m use BDF-i (the lower orders start the method).
   */
  struct BDFCoefficients
  {
    std::vector<double> alpha; ///< alpha_1..alpha_m (index 0 is alpha_1)
    double              beta;
  };

  /// Coefficients of BDF-`order` (1 <= order <= 6).
  BDFCoefficients
  bdf_coefficients(const unsigned int order);

  /// Coefficients used at step `step` (1-based) of a BDF-`order` run.
  inline BDFCoefficients
  bdf_coefficients_at_step(const unsigned int order, const unsigned int step)
  {
    return bdf_coefficients(step < order ? step : order);
  }
} // namespace forma

#endif
