// Mode = optimize of the elasticity apps (see jobs.cc), private to the
// library.

#ifndef forma_elasticity_optimize_job_h
#define forma_elasticity_optimize_job_h

#include <forma/elasticity/jobs.h>
#include <forma/optimization/optimizer.h>

#include <vector>

namespace forma
{
  /// Thesis Algorithm 1 around the optimizer: L-BFGS runs, one per mesh,
  /// separated by remeshes, holds of blocked vertices and element removal;
  /// then the summary. Returns the final design.
  template <int dim>
  std::vector<double>
  optimize_job(const ElasticityParameters   &parameters,
               const OptimizationParameters &settings,
               RunContext                   &context,
               const DesignConstraint       *constraint);
} // namespace forma

#endif
