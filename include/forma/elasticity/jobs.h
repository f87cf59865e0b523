#ifndef forma_elasticity_jobs_h
#define forma_elasticity_jobs_h

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace forma
{
  class RunContext;
  struct ElasticityParameters;

  /**
   * The jobs of the elasticity-based apps (forma-transient-ipc,
   * forma-contact-assembly): `simulate` (run and write VTU/PVD),
   * `verify gradient` (Taylor test of the objective's adjoint gradient,
   * Gradient check section) and `optimize` (ROL with remeshing, Optimization
   * section: history, convergence.png, VTU per iteration).
   */
  void
  run_elasticity_job(const std::string          &mode,
                     const ElasticityParameters &parameters,
                     dealii::ParameterHandler   &prm,
                     RunContext                 &context);

  /// Declare the sections run_elasticity_job() reads besides
  /// ElasticityParameters (gradient check, optimization).
  void
  declare_elasticity_job_parameters(dealii::ParameterHandler &prm);
} // namespace forma

#endif
