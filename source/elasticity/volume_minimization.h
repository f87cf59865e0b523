// Thesis Table 2.2's "Post vol. min.": the objective of the stage that
// minimizes the volume once the stress has been minimized (private to the
// library, see optimize_job.cc).

#ifndef forma_elasticity_volume_minimization_h
#define forma_elasticity_volume_minimization_h

#include <forma/adjoint/registry.h>

#include <string>

namespace forma
{
  /// The one `stress` or `von mises` record of Objective/Terms `terms`;
  /// throws (naming Optimization/Volume minimization iterations) unless
  /// there is exactly one.
  KeyValueRecord
  stress_term_of(const std::string &terms);

  /**
   * Objective/Terms of the volume stage: k (J0 (V / V1 + w max(S / S1 - 1
   * - slack, 0)^2) + the other terms of `terms`) with k = `scale` (the
   * stress and volume terms go; the others keep their keys, weights times
   * k). S is the L^p norm of the stress term (its p and material), V the
   * volume of that material (all, without one); S1 and V1 their values at
   * the start of the stage, J0 > 0 the scale of the first stage's
   * objective.
   */
  std::string
  volume_minimization_terms(const std::string &terms,
                            const double       J0,
                            const double       S1,
                            const double       V1,
                            const double       slack,
                            const double       w,
                            const double       scale);
} // namespace forma

#endif
