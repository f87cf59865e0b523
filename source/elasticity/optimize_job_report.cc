// Mode = optimize: the results: the printed lines, summary.json and the
// convergence history.

#include <forma/adjoint/objective.h>
#include <forma/base/plot.h>
#include <forma/base/records.h>
#include <forma/elasticity/load_cases.h>

#include "optimize_job_impl.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace forma
{
  namespace internal
  {
    std::string
    describe_design(const DesignLayout        &layout,
                    const std::vector<double> &q0,
                    const std::vector<double> &q,
                    const double               shape_offset,
                    nlohmann::json            &json)
    {
      using Summary = DesignBlock::Summary;
      std::string text;
      for (const auto &b : layout.blocks)
        {
          if (b.summary != Summary::values)
            {
              // Shape: largest vertex move from the mesh as read (of the
              // shape the simulator holds); cell materials: largest change.
              const bool shape = b.summary == Summary::vertex_offset;
              double     m     = shape ? shape_offset : 0.;
              if (!shape)
                for (unsigned int i = b.offset; i < b.offset + b.size; ++i)
                  m = std::max(m, std::abs(q[i] - q0[i]));
              const std::string what =
                shape ? "max vertex offset from the mesh" : "max change";
              json[b.name + ": " + what] = m;
              text += (text.empty() ? "" : "; ") + b.name + ": " + what + " " +
                      sig(m, 3);
              continue;
            }
          if (b.size > 8)
            {
              double m = 0;
              for (unsigned int i = b.offset; i < b.offset + b.size; ++i)
                m = std::max(m, std::abs(q[i]));
              json[b.name + ": max |value|"] = m;
              text += (text.empty() ? "" : "; ") + b.name + ": max |value| " +
                      sig(m, 3);
              continue;
            }
          std::vector<double> v(q.begin() + b.offset,
                                q.begin() + b.offset + b.size);
          json[b.name] = v;
          text += (text.empty() ? "" : "; ") + b.name + ":";
          for (const double x : v)
            text += " " + sig(x, 6);
        }
      return text;
    }



    // Per outer iteration: where it started, its weights and what it
    // lowered J by on its own mesh and weights (its first value to its
    // last, before the remesh).
    template <int dim>
    nlohmann::json
    OptimizeJob<dim>::outer_summary() const
    {
      const double   J0    = result.history.front();
      nlohmann::json outer = nlohmann::json::array();
      for (unsigned int i = 0; i < outer_starts.size(); ++i)
        {
          const double last_J =
            i < outer_last_J.size() ? outer_last_J[i] : result.history.back();
          outer.push_back(
            {{"iteration", outer_starts[i]},
             {"weights",
              i < outer_weights.size() ? outer_weights[i] : nlohmann::json()},
             {"reduction_percent",
              100 * (result.history[outer_starts[i]] - last_J) /
                std::abs(J0)}});
        }
      return outer;
    }



    template <int dim>
    void
    OptimizeJob<dim>::report()
    {
      ensure(result.design);
      const nlohmann::json state1 = simulator.state_statistics();
      nlohmann::json       final_values;
      const auto           text = describe_design(simulator.design_layout(),
                                        model.initial,
                                        result.design,
                                        simulator.max_shape_offset(),
                                        final_values);
      print_results(state1, text);
      write_summary(state1, final_values);
      write_history();
    }



    // Thesis Table 2.2's last two columns: the last gradient norm over the
    // first, and what the last outer iteration lowered J by (% of J0).
    template <int dim>
    double
    OptimizeJob<dim>::relative_gradient_norm() const
    {
      return first_gradient_norm > 0 ?
               last_gradient_norm / first_gradient_norm :
               0;
    }



    template <int dim>
    double
    OptimizeJob<dim>::last_outer_reduction() const
    {
      return outer_start < result.history.size() ?
               100 * (result.history[outer_start] - result.history.back()) /
                 std::abs(result.history.front()) :
               0;
    }



    // "objective J0 -> J1 (ratio)"; with a volume stage, each stage's
    // objective from its start to its end (the stress stage's end is not
    // known to a run resumed after it).
    template <int dim>
    std::string
    OptimizeJob<dim>::objective_line() const
    {
      const auto change = [](const double a, const double b) {
        return sig(a, 6) + " -> " + sig(b, 6) + " (ratio " + sig(b / a, 4) +
               ")";
      };
      const double J0 = result.history.front(), J1 = result.history.back();
      if (stage_terms.empty())
        return "objective " + change(J0, J1);
      std::string line =
        "volume stage's objective " + change(result.history[stage_start], J1);
      if (!std::isnan(stress_stage_J))
        line = "objective " + change(J0, stress_stage_J) + ", " + line;
      return line;
    }



    template <int dim>
    void
    OptimizeJob<dim>::print_results(const nlohmann::json &state1,
                                    const std::string    &design_text) const
    {
      context.print("stopped after " +
                    std::to_string(result.history.size() - 1) +
                    " iterations: " + result.stop_reason);
      context.log("outer iterations (meshes) " + std::to_string(n_outer) +
                  ", relative gradient norm " +
                  sig(relative_gradient_norm(), 3) +
                  ", the last one's reduction of J " +
                  sig(last_outer_reduction(), 3) + "% of J0");
      context.print(objective_line());
      for (const auto &[key, label] :
           {std::pair<std::string, std::string>{"max_stress",
                                                "max stress (Frobenius)"},
            {"max_von_mises_stress", "max von Mises stress"},
            {"volume", "volume"}})
        context.print(label + " " + sig(double(state0[key]), 5) + " -> " +
                      sig(double(state1[key]), 5) + " (ratio " +
                      sig(double(state1[key]) / double(state0[key]), 4) + ")");
      if (!design_text.empty())
        context.print("final design: " + design_text);
    }



    template <int dim>
    void
    OptimizeJob<dim>::write_summary(const nlohmann::json &state1,
                                    const nlohmann::json &final_values)
    {
      const double J0 = result.history.front(), J1 = result.history.back();
      auto        &o = context.summary["optimization"];
      o              = {{"initial_objective", J0},
                        {"final_objective", J1},
                        {"ratio", J1 / J0},
                        {"iterations", result.history.size() - 1},
                        {"stop_reason", result.stop_reason},
                        {"initial_state", state0},
                        {"final_state", state1},
                        {"remeshes", remeshes},
                        {"holds", holds},
                        {"outer_iterations", n_outer},
                        {"max_outer_iterations", settings.outer_iterations},
                        {"outer", outer_summary()},
                        {"relative_gradient_norm", relative_gradient_norm()},
                        {"last_outer_reduction_percent", last_outer_reduction()},
                        {"final_design", final_values}};
      if (!stage_terms.empty())
        o["volume_minimization"] = {{"iteration", stage_start},
                                    {"terms", stage_terms},
                                    {"start_state", stage_start_state},
                                    {"stress_stage_final_objective",
                                     std::isnan(stress_stage_J) ?
                                       nlohmann::json() :
                                       nlohmann::json(stress_stage_J)},
                                    {"stress_stage_stop_reason",
                                     stress_stage_stop}};
      context.summary["adjoint"] = simulator.adjoint_statistics();
      // Where the run's time went (thesis Algorithm 1's parts); 'other' is
      // the optimizer, the line search's quality checks and the output.
      const auto  &a     = context.summary["adjoint"];
      const double total = wall_timer.wall_time();
      const double parts = double(a["forward_seconds"]) +
                           double(a["adjoint_seconds"]) + remesh_seconds;
      context.summary["timing"] = {
        {"total_seconds", total},
        {"forward_seconds", a["forward_seconds"]},
        {"adjoint_solve_seconds", a["adjoint_solve_seconds"]},
        {"derivative_products_seconds", a["derivative_products_seconds"]},
        {"remesh_seconds", remesh_seconds},
        {"other_seconds", total - parts}};
      // The key numbers at the top level (thesis Table 2.2 columns).
      context.summary["initial_objective"]  = J0;
      context.summary["final_objective"]    = J1;
      context.summary["initial_max_stress"] = state0["max_stress"];
      context.summary["final_max_stress"]   = state1["max_stress"];
      context.summary["initial_volume"]     = state0["volume"];
      context.summary["final_volume"]       = state1["volume"];
    }



    template <int dim>
    void
    OptimizeJob<dim>::write_history() const
    {
      if (!context.is_root())
        return;
      std::ofstream csv(context.path("history.csv"));
      csv << "iteration,objective\n";
      for (unsigned int k = 0; k < result.history.size(); ++k)
        csv << k << ',' << std::setprecision(12) << result.history[k] << '\n';
      write_history_plot(context.path("convergence.png"),
                         result.history,
                         "objective history",
                         "iteration",
                         {outer_starts.begin() + 1, outer_starts.end()},
                         "remesh (new outer iteration)");
    }



    template class OptimizeJob<2>;
    template class OptimizeJob<3>;
  } // namespace internal
} // namespace forma
