#include <forma/elasticity/load_cases.h>
#include <forma/elasticity/simulator.h>
#include <forma/elasticity/taylor_test.h>

#include <memory>
#include <sstream>

namespace forma
{
  template <typename Model>
  GradientCheckResult
  taylor_test(Model                                          &simulator,
              const GradientCheckParameters                  &parameters,
              const std::function<void(const std::string &)> &log)
  {
    const std::vector<double> q = simulator.design();
    const std::vector<double> theta =
      random_direction(simulator.design_layout(),
                       simulator.design_scales(q),
                       parameters);
    // Adaptive time steps: every evaluation, the one at q too, replays the
    // levels chosen at q (an adaptive solve's path, e.g. its rejected
    // attempts, may differ from a replay's within the solver tolerances);
    // unfrozen also if an evaluation throws.
    if (simulator.adaptive_time_steps())
      {
        simulator.set_design(q);
        simulator.solve_design();
      }
    simulator.freeze_time_steps(true);
    const auto unfreeze = [](Model *m) { m->freeze_time_steps(false); };
    const std::unique_ptr<Model, decltype(unfreeze)> frozen(&simulator,
                                                            unfreeze);
    auto                                             result = taylor_test(
      [&](const std::vector<double> &x) {
        simulator.set_design(x);
        simulator.solve_design();
        const double J = simulator.objective();
        if (log)
          {
            std::ostringstream s;
            s.precision(16);
            s << "  Taylor test: J = " << J;
            log(s.str());
          }
        return J;
      },
      [&](const std::vector<double> &x, std::vector<double> &dJ) {
        simulator.set_design(x);
        simulator.solve_design();
        return simulator.gradient(dJ);
      },
      q,
      theta,
      parameters);
    simulator.set_design(q);
    return result;
  }

  template GradientCheckResult
  taylor_test(ElasticitySimulator<2> &,
              const GradientCheckParameters &,
              const std::function<void(const std::string &)> &);
  template GradientCheckResult
  taylor_test(ElasticitySimulator<3> &,
              const GradientCheckParameters &,
              const std::function<void(const std::string &)> &);
  template GradientCheckResult
  taylor_test(LoadCases<2> &,
              const GradientCheckParameters &,
              const std::function<void(const std::string &)> &);
  template GradientCheckResult
  taylor_test(LoadCases<3> &,
              const GradientCheckParameters &,
              const std::function<void(const std::string &)> &);
} // namespace forma
