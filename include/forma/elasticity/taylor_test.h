#ifndef forma_elasticity_taylor_test_h
#define forma_elasticity_taylor_test_h

#include <forma/adjoint/gradient_check.h>
#include <forma/elasticity/simulator.h>

#include <functional>
#include <string>

namespace forma
{
  /**
   * Taylor test of a model's adjoint gradient at its current design, along
   * a random direction (random_direction() with the mesh's cell size):
   * `prepare()` and `set_objective()` must have been called. `log` receives
   * one line per row. The model (an ElasticitySimulator or LoadCases) is
   * left at the starting design.
   */
  template <typename Model>
  GradientCheckResult
  taylor_test(Model                                          &model,
              const GradientCheckParameters                  &parameters,
              const std::function<void(const std::string &)> &log = {});
} // namespace forma

#endif
