#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>

#include <forma/adjoint/gradient_check.h>
#include <forma/base/plot.h>
#include <forma/base/run_context.h>
#include <forma/optimization/optimizer.h>
#include <forma/rhombic/inverse_problem.h>

#include "modes.h"

#include <cmath>
#include <map>
#include <memory>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    void
    inverse_mode(ParameterHandler &prm, const Setup &setup, RunContext &context)
    {
      const RhombicStructure s0 = read_structure(prm, setup);
      const InverseProblem   problem =
        InverseProblem::read(prm, setup, s0, context.communicator());
      const OptimizationParameters op =
        inverse_optimization_parameters(prm, problem.tolerance);

      std::vector<nlohmann::json> iterations;
      const auto                  accepted =
        [&](const unsigned int k, const CellModel &cell, const double J) {
          const auto    &r = cell.sample();
          nlohmann::json j = structure_json(cell.structure());
          j["iteration"]   = k;
          j["objective"]   = J;
          j["E_over_Eb"]   = r.fit.E / setup.base.E;
          j["nu"]          = r.fit.nu;
          j["a1"]          = r.anisotropy.a1;
          j["a2"]          = r.anisotropy.a2;
          j["misfit"]      = problem.misfit(r);
          iterations.push_back(j);
        };

      context.print("inverse: target " +
                    std::string(problem.target_structure[0] != 0 ?
                                  "the C^H of a structure, isotropic fit " :
                                  "") +
                    "E/E_b = " + sig(problem.target_E) +
                    ", nu = " + sig(problem.target_nu) + " on a " +
                    sig(s0.alpha * 180 / M_PI) + " degree cell, " +
                    std::to_string(problem.free.size()) + " free parameters");
      const InverseSolution result =
        problem.solve(s0, setup, context.communicator(), op, context, accepted);
      const auto  &r      = result.sample;
      const double misfit = result.misfit;
      context.print("inverse: E/E_b = " + sig(r.fit.E / setup.base.E) +
                    ", nu = " + sig(r.fit.nu) +
                    ", a1 = " + sig(r.anisotropy.a1, 2) +
                    ", a2 = " + sig(r.anisotropy.a2, 2) + "; |C - C*|/|C*| = " +
                    sig(misfit, 3) + " (" + result.stop_reason + ")");
      std::string p;
      for (const double v : result.structure.p)
        p += (p.empty() ? "" : ", ") + sig(v);
      context.print("inverse: p = " + p);
      nlohmann::json &S = context.summary;
      S["target"]       = {{"E_over_Eb", problem.target_E},
                           {"nu", problem.target_nu}};
      if (problem.target_structure[0] != 0)
        S["target"]["parameters"] = problem.target_structure;
      S["start"]       = structure_json(s0);
      S["structure"]   = structure_json(result.structure);
      S["result"]      = sample_json(r, setup);
      S["misfit"]      = misfit;
      S["reached"]     = misfit <= problem.tolerance;
      S["stop_reason"] = result.stop_reason;
      S["history"]     = iterations;
      if (context.is_root())
        {
          write_history_plot(context.path("convergence.png"),
                             result.history,
                             "Inverse homogenization",
                             "iteration");
          write_structure_png(context.path("structure.png"), result.structure);
        }
    }



    void
    verify_gradient_mode(ParameterHandler &prm,
                         const Setup      &setup,
                         RunContext       &context)
    {
      const RhombicStructure s0 = read_structure(prm, setup);
      const InverseProblem   problem =
        InverseProblem::read(prm, setup, s0, context.communicator());
      GradientCheckParameters gc;
      gc.parse(prm);
      // The discrete map the gradient differentiates: the cell mesh moved
      // to each design (same topology).
      CellModel  model(s0, setup, context.communicator());
      const auto z0 = problem.free_values(s0);
      // A deterministic direction of moderate steps in every parameter.
      std::vector<double> direction;
      for (unsigned int k = 0; k < z0.size(); ++k)
        direction.push_back(std::sin(1.0 + gc.seed + 2.3 * k));
      const auto objective = [&](const std::vector<double> &z) {
        model.move_to(problem.with(s0, z));
        return problem.objective(model, nullptr);
      };
      const auto gradient = [&](const std::vector<double> &z,
                                std::vector<double>       &g) {
        AssertThrow(z == z0, ExcInternalError());
        return problem.objective(model, &g);
      };
      const GradientCheckResult r =
        taylor_test(objective, gradient, z0, direction, gc);
      context.print("verify gradient: J = " + sig(r.value, 6) +
                    ", dJ . theta = " + sig(r.directional_derivative, 6));
      for (unsigned int k = 0; k < r.epsilons.size(); ++k)
        context.print("  eps = " + sig(r.epsilons[k], 3) + ": error " +
                      sig(r.errors[k], 3) +
                      (k > 0 && std::isfinite(r.rates[k - 1]) ?
                         ", rate " + sig(r.rates[k - 1], 3) :
                         std::string()));
      context.print("verify gradient: minimum rate " + sig(r.min_rate, 3) +
                    (r.min_rate > 1.8 ? " (ok)" : " (TOO LOW)"));
      context.summary["gradient_check"] = r.to_json();
      context.summary["structure"]      = structure_json(s0);
    }
  } // namespace rhombic
} // namespace forma
