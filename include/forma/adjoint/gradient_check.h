#ifndef forma_adjoint_gradient_check_h
#define forma_adjoint_gradient_check_h

#include <deal.II/base/parameter_handler.h>

#include <forma/adjoint/design.h>

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace forma
{
  /// The `Gradient check` section.
  struct GradientCheckParameters
  {
    double       first_step = 1e-2; ///< epsilon of the first row
    unsigned int n_steps    = 5;    ///< rows; epsilon halves per row
    unsigned int seed       = 1;    ///< of the random direction
    std::string  blocks;            ///< blocks to perturb; empty: all

    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(dealii::ParameterHandler &prm);
  };

  /// The Taylor table: epsilon, |J(q + eps theta) - J(q) - eps dJ.theta|.
  struct GradientCheckResult
  {
    double              value                  = 0;
    double              directional_derivative = 0;
    std::vector<double> epsilons, values, errors;
    std::vector<double> rates; ///< log2(e_k / e_{k+1}); NaN where both
                               ///< errors are at round-off level
    double min_rate = 0;       ///< over the valid rates; NaN if none

    nlohmann::json
    to_json() const;
  };

  /**
   * A random direction theta for a Taylor test, deterministic in `seed`:
   * entries uniform in [-1, 1] times `scales` (the design's, so that eps =
   * 1 is a large but meaningful change), zero outside the blocks of
   * `parameters` (all if none are named).
   */
  std::vector<double>
  random_direction(const DesignLayout            &layout,
                   const std::vector<double>     &scales,
                   const GradientCheckParameters &parameters);

  /**
   * Taylor test of a gradient (thesis ch. 3; DESIGN.md section 2): the
   * error of the first-order expansion must fall as eps^2. `objective`
   * evaluates J at a design; `gradient` returns J and dJ/dq at q.
   */
  GradientCheckResult
  taylor_test(
    const std::function<double(const std::vector<double> &)> &objective,
    const std::function<double(const std::vector<double> &,
                               std::vector<double> &)>       &gradient,
    const std::vector<double>                                &q,
    const std::vector<double>                                &direction,
    const GradientCheckParameters                            &parameters);
} // namespace forma

#endif
