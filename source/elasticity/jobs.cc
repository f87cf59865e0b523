// The jobs shared by the elasticity-based apps (see forma/elasticity/jobs.h).

#include <deal.II/base/exceptions.h>

#include <forma/adjoint/gradient_check.h>
#include <forma/base/application.h>
#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/elasticity/jobs.h>
#include <forma/elasticity/load_cases.h>
#include <forma/elasticity/parameters.h>
#include <forma/elasticity/simulator.h>
#include <forma/elasticity/taylor_test.h>
#include <forma/optimization/optimizer.h>

#include "optimize_job.h"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace
{
  std::string
  fixed(const double x, const int digits)
  {
    if (!std::isfinite(x))
      return "n/a";
    std::ostringstream s;
    s << std::fixed << std::setprecision(digits) << x;
    return s.str();
  }

  template <int dim>
  void
  simulate_job(const forma::ElasticityParameters &parameters,
               forma::RunContext                 &context)
  {
    AssertThrow(dealii::Utilities::trim(parameters.load_cases).empty(),
                dealii::ExcMessage(
                  "Mode = simulate runs one load case: move the case to "
                  "Boundary conditions/Traction and clear Load cases (e.g. "
                  "--set 'Boundary conditions/Load cases='), or use Mode = "
                  "optimize with Optimization/Max iterations = 0."));
    forma::ElasticitySimulator<dim> simulator(parameters,
                                              context.communicator());
    simulator.run(&context);
  }

  template <int dim>
  void
  verify_gradient_job(forma::ElasticityParameters           parameters,
                      const forma::GradientCheckParameters &check,
                      forma::RunContext                    &context)
  {
    // The Taylor remainder is compared with J to ~1e-10: converge Newton
    // well below that.
    parameters.newton_relative_tolerance =
      std::min(parameters.newton_relative_tolerance, 1e-12);
    parameters.newton_absolute_tolerance =
      std::min(parameters.newton_absolute_tolerance, 1e-14);
    forma::LoadCases<dim> simulator(parameters, context.communicator());
    simulator.prepare(&context);
    AssertThrow(simulator.design_layout().size() > 0,
                dealii::ExcMessage("Design/Parameters is empty: there is "
                                   "nothing to differentiate."));
    simulator.set_objective(parameters.objective);
    if (simulator.n_cases() > 1)
      context.print(std::to_string(simulator.n_cases()) + " load cases");

    std::string blocks;
    for (const auto &b : simulator.design_layout().blocks)
      blocks += (blocks.empty() ? "" : ", ") + b.name + " (" +
                std::to_string(b.size) + ")";
    context.print("design: " + blocks);

    const auto result =
      forma::taylor_test(simulator, check, [&](const std::string &line) {
        context.log(line);
      });

    context.print("J = " + forma::sig(result.value, 6) + ", dJ . theta = " +
                  forma::sig(result.directional_derivative, 6));
    for (unsigned int k = 0; k < result.epsilons.size(); ++k)
      context.log("  epsilon " + forma::sig(result.epsilons[k], 4) +
                  ": J = " + forma::sig(result.values[k], 16) +
                  ", Taylor error " + forma::sig(result.errors[k], 4));
    std::string rates;
    for (const double r : result.rates)
      rates += (rates.empty() ? "" : " ") + fixed(r, 1);
    context.print("Taylor test rates (epsilon halving): " + rates);
    // No valid rate: every error is at round-off level, i.e. J is linear
    // along theta and the first-order expansion is exact.
    const bool exact = std::isnan(result.min_rate);
    const bool pass  = exact || result.min_rate >= 1.9;
    context.print(exact ? "Taylor errors at round-off level: J is linear "
                          "along the direction, gradient exact" :
                          "min rate " + fixed(result.min_rate, 1) +
                            (pass ? ": gradient verified (>= 1.9)" :
                                    ": GRADIENT CHECK FAILED (< 1.9)"));
    context.summary["gradient_check"]           = result.to_json();
    context.summary["gradient_check"]["passed"] = pass;
    context.summary["adjoint"] = simulator.adjoint_statistics();
    if (parameters.time_integrator == "adaptive")
      {
        const auto &a = context.summary["adjoint"];
        context.print(
          "on adaptive time steps: " +
          std::to_string(a["time_steps"].get<unsigned int>()) + " steps from " +
          forma::sig(a["smallest_time_step"].get<double>(), 3) + " to " +
          forma::sig(a["largest_time_step"].get<double>(), 3));
        if (parameters.variable_order)
          {
            std::string counts;
            for (const auto &n : a["steps_per_order"])
              counts += " " + std::to_string(n.get<unsigned int>());
            context.print("steps per BDF order (1 to " +
                          std::to_string(parameters.bdf_order) + "):" + counts);
          }
      }
    AssertThrow(pass,
                dealii::ExcMessage("the Taylor test failed: min rate " +
                                   fixed(result.min_rate, 2) +
                                   " < 1.9 (table in summary.json)."));
  }
} // namespace

namespace forma
{
  void
  declare_elasticity_job_parameters(dealii::ParameterHandler &prm)
  {
    GradientCheckParameters::declare(prm);
    OptimizationParameters::declare(prm);
  }



  namespace
  {
    DeclExceptionMsg(ExcNoDesignConstraint,
                     "design constraints are for 2D optimizations only");

    using Job = std::function<std::vector<double>(const ElasticityParameters &,
                                                  dealii::ParameterHandler &,
                                                  RunContext &,
                                                  const DesignConstraint *)>;

    /// The jobs by name, in the order the apps list them.
    const std::vector<std::pair<std::string, Job>> &
    jobs()
    {
      static const std::vector<std::pair<std::string, Job>> list = {
        {"simulate",
         [](const ElasticityParameters &parameters,
            dealii::ParameterHandler &,
            RunContext             &context,
            const DesignConstraint *constraint) {
           AssertThrow(!constraint, ExcNoDesignConstraint());
           if (parameters.dim == 2)
             simulate_job<2>(parameters, context);
           else
             simulate_job<3>(parameters, context);
           return std::vector<double>();
         }},
        {"verify gradient",
         [](const ElasticityParameters &parameters,
            dealii::ParameterHandler   &prm,
            RunContext                 &context,
            const DesignConstraint     *constraint) {
           AssertThrow(!constraint, ExcNoDesignConstraint());
           GradientCheckParameters check;
           check.parse(prm);
           if (parameters.dim == 2)
             verify_gradient_job<2>(parameters, check, context);
           else
             verify_gradient_job<3>(parameters, check, context);
           return std::vector<double>();
         }},
        {"optimize",
         [](const ElasticityParameters &parameters,
            dealii::ParameterHandler   &prm,
            RunContext                 &context,
            const DesignConstraint     *constraint) {
           OptimizationParameters settings;
           settings.parse(prm);
           if (parameters.dim == 2)
             return optimize_job<2>(parameters, settings, context, constraint);
           AssertThrow(!constraint, ExcNoDesignConstraint());
           return optimize_job<3>(parameters, settings, context, nullptr);
         }}};
      return list;
    }
  } // namespace



  std::vector<double>
  run_elasticity_job(const std::string          &mode,
                     const ElasticityParameters &parameters,
                     dealii::ParameterHandler   &prm,
                     RunContext                 &context,
                     const DesignConstraint     *constraint)
  {
    for (const auto &[name, job] : jobs())
      if (name == mode)
        return job(parameters, prm, context, constraint);
    AssertThrow(false, dealii::ExcMessage("unknown Mode '" + mode + "'."));
    return {};
  }



  std::vector<ApplicationMode>
  elasticity_modes(
    const std::function<ElasticityParameters(dealii::ParameterHandler &,
                                             const std::string &)> &parse)
  {
    std::vector<ApplicationMode> modes;
    for (const auto &[name, job] : jobs())
      modes.push_back({name,
                       [parse, job = job](dealii::ParameterHandler &prm,
                                          const std::string        &dir,
                                          RunContext               &context) {
                         job(parse(prm, dir), prm, context, nullptr);
                       }});
    return modes;
  }
} // namespace forma
