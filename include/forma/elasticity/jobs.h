#ifndef forma_elasticity_jobs_h
#define forma_elasticity_jobs_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>

#include <forma/base/application.h>
#include <forma/elasticity/parameters.h>

#include <functional>
#include <string>
#include <vector>

namespace forma
{
  class RunContext;
  struct DesignLayout;

  /**
   * What an application adds to an elasticity optimization (e.g. forma-
   * rhombic: per-cell materials inside the coverage of a microstructure
   * family): `setup` tightens the bounds, knowing the layout and the cell
   * centers (by global active cell index, the order of the `cell material`
   * block); `penalty` is a soft constraint P(q) >= 0 that adds its
   * gradient to `dP` and whose value, in units of |J(q0)|, is added to J.
   */
  struct DesignConstraint
  {
    std::function<void(const DesignLayout                  &layout,
                       const std::vector<dealii::Point<2>> &cell_centers,
                       std::vector<double>                 &lower,
                       std::vector<double>                 &upper)>
      setup;
    std::function<double(const std::vector<double> &q, std::vector<double> &dP)>
      penalty;
  };

  /**
   * The jobs of the elasticity-based apps (forma-transient-ipc,
   * forma-contact-assembly): `simulate` (run and write VTU/PVD),
   * `verify gradient` (Taylor test of the objective's adjoint gradient,
   * Gradient check section) and `optimize` (ROL with remeshing, Optimization
   * section: history, convergence.png, VTU per iteration).
   */
  /// Returns the final design of `optimize` (empty for the other jobs). A
  /// `constraint` (2D `optimize` only) joins the optimization.
  std::vector<double>
  run_elasticity_job(const std::string          &mode,
                     const ElasticityParameters &parameters,
                     dealii::ParameterHandler   &prm,
                     RunContext                 &context,
                     const DesignConstraint     *constraint = nullptr);

  /// The jobs as the modes of an application; `parse` reads the problem
  /// (ElasticityParameters with the app's contact sections).
  std::vector<ApplicationMode>
  elasticity_modes(
    const std::function<ElasticityParameters(dealii::ParameterHandler &,
                                             const std::string &prm_directory)>
      &parse);

  /// Declare the sections run_elasticity_job() reads besides
  /// ElasticityParameters (gradient check, optimization).
  void
  declare_elasticity_job_parameters(dealii::ParameterHandler &prm);
} // namespace forma

#endif
