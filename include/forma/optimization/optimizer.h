#ifndef forma_optimization_optimizer_h
#define forma_optimization_optimizer_h

#include <deal.II/base/parameter_handler.h>

#include <functional>
#include <string>
#include <vector>

namespace forma
{
  class RunContext;

  /// The `Optimization` section.
  struct OptimizationParameters
  {
    unsigned int max_iterations     = 50;
    double       relative_decrease  = 1e-3; ///< epsilon_r of thesis ch. 2.5
    unsigned int decrease_window    = 2;    ///< m of thesis ch. 2.5
    double       gradient_tolerance = 1e-6; ///< relative to the first one
    unsigned int memory             = 10;   ///< L-BFGS pairs
    bool         resume             = false;

    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(dealii::ParameterHandler &prm);
  };

  /**
   * What the optimizer drives. `value` and `gradient` throw (any exception)
   * when the design is inadmissible or its forward solve fails; the
   * optimizer then treats the trial as a failed step and shortens it.
   * `scale` maps optimization variables z to designs, q = q0 + scale * z,
   * so that every entry moves on a comparable scale (cell sizes for
   * vertices, the values themselves for material constants).
   */
  struct DesignModel
  {
    std::vector<double> initial, scale, lower, upper;
    std::function<double(const std::vector<double> &)> value;
    std::function<double(const std::vector<double> &, std::vector<double> &)>
      gradient;
    /// Called for the starting design (iteration 0) and every accepted one.
    std::function<void(unsigned int, const std::vector<double> &, double)>
      accepted;
  };

  struct OptimizationResult
  {
    std::vector<double> design;
    std::vector<double> history; ///< J of the accepted iterates, first J0
    std::string         stop_reason;
  };

  /**
   * Minimize with ROL: a line-search L-BFGS method, projected onto the
   * bounds (lower/upper, +-inf where free). Stops when the objective fell
   * by less than `relative_decrease` * |J0| over `decrease_window`
   * iterations (thesis ch. 2.5), the gradient fell below
   * `gradient_tolerance` relative to the first one, the step vanished, or
   * after `max_iterations`. After every accepted iterate the design is
   * written to `<output directory>/optimization.checkpoint.json`; with
   * `resume` the run continues from that file (the L-BFGS memory restarts).
   */
  OptimizationResult
  optimize(const DesignModel            &model,
           const OptimizationParameters &parameters,
           RunContext                   &context);
} // namespace forma

#endif
