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

  /// Where the volume stage starts and how it holds the stress.
  struct VolumeStage
  {
    double J0        = 1;    ///< |J| of the first objective at its start
    double V1        = 1;    ///< the volume of the stress term's material
    double norm      = 1;    ///< S1: the stress term's L^p norm
    double peak      = 1;    ///< s1: its largest stress (its material, measure)
    bool   hold_peak = true; ///< hold s1 pointwise, else S1
    double slack     = 0.02;
    double weight    = 1e5; ///< w
    double scale     = 1;   ///< k
  };

  /**
   * Objective/Terms of the volume stage: k (J0 (V / V1 + w P) + the other
   * terms of `terms`). The stress and volume terms go; the others keep
   * their keys, with weights times k. V is the volume of the stress term's
   * material (all parts without one). P holds the stress: with `hold_peak`
   * int max(s - (1 + slack) s1, 0)^2 / (s1^2 V1) of the stress term's
   * measure s (a `stress bound` or `von mises bound` term), else max(S /
   * S1 - 1 - slack, 0)^2 of its L^p norm S (a `stress norm bound` term).
   */
  std::string
  volume_minimization_terms(const std::string &terms, const VolumeStage &stage);
} // namespace forma

#endif
