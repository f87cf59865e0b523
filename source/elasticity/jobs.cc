// The jobs shared by the elasticity-based apps (see forma/elasticity/jobs.h).

#include <deal.II/base/exceptions.h>
#include <deal.II/base/timer.h>

#include <forma/adjoint/gradient_check.h>
#include <forma/adjoint/objective.h>
#include <forma/base/application.h>
#include <forma/base/plot.h>
#include <forma/base/run_context.h>
#include <forma/elasticity/element_removal.h>
#include <forma/elasticity/jobs.h>
#include <forma/elasticity/load_cases.h>
#include <forma/elasticity/parameters.h>
#include <forma/elasticity/simulator.h>
#include <forma/elasticity/taylor_test.h>
#include <forma/optimization/optimizer.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <set>
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

  std::string
  significant(const double x, const int digits)
  {
    std::ostringstream s;
    s << std::setprecision(digits) << x;
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

    context.print("J = " + significant(result.value, 6) + ", dJ . theta = " +
                  significant(result.directional_derivative, 6));
    for (unsigned int k = 0; k < result.epsilons.size(); ++k)
      context.log("  epsilon " + significant(result.epsilons[k], 4) +
                  ": J = " + significant(result.values[k], 16) +
                  ", Taylor error " + significant(result.errors[k], 4));
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
          significant(a["smallest_time_step"].get<double>(), 3) + " to " +
          significant(a["largest_time_step"].get<double>(), 3));
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

  // Values of the small (non-shape) design blocks, e.g. recovered materials.
  std::string
  describe_design(const forma::DesignLayout &layout,
                  const std::vector<double> &q0,
                  const std::vector<double> &q,
                  const double               shape_offset,
                  nlohmann::json            &json)
  {
    using Summary = forma::DesignBlock::Summary;
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
                    significant(m, 3);
            continue;
          }
        if (b.size > 8)
          {
            double m = 0;
            for (unsigned int i = b.offset; i < b.offset + b.size; ++i)
              m = std::max(m, std::abs(q[i]));
            json[b.name + ": max |value|"] = m;
            text += (text.empty() ? "" : "; ") + b.name + ": max |value| " +
                    significant(m, 3);
            continue;
          }
        std::vector<double> v(q.begin() + b.offset,
                              q.begin() + b.offset + b.size);
        json[b.name] = v;
        text += (text.empty() ? "" : "; ") + b.name + ":";
        for (const double x : v)
          text += " " + significant(x, 6);
      }
    return text;
  }

  // "name w, ..." of the terms whose weights ramp (thesis Algorithm 1).
  template <int dim>
  std::string
  ramped_weights(const forma::LoadCases<dim> &simulator)
  {
    std::string text;
    for (const auto &[name, weight] : simulator.ramped_weights())
      text += (text.empty() ? "" : ", ") + name + " " + significant(weight, 4);
    return text;
  }



  template <int dim>
  std::vector<double>
  optimize_job(const forma::ElasticityParameters   &parameters,
               const forma::OptimizationParameters &settings,
               forma::RunContext                   &context,
               const forma::DesignConstraint       *constraint)
  {
    forma::LoadCases<dim> simulator(parameters, context.communicator());
    simulator.prepare(&context);
    const auto &layout = simulator.design_layout();
    AssertThrow(layout.size() > 0,
                dealii::ExcMessage("Design/Parameters is empty: there is "
                                   "nothing to optimize."));
    simulator.set_objective(parameters.objective);
    if (simulator.n_cases() > 1)
      context.print(std::to_string(simulator.n_cases()) +
                    " load cases; VTU frames show the first");

    // The simulator keeps the last solved design; solve only when q moves.
    std::vector<double> solved;
    auto                ensure = [&](const std::vector<double> &q) {
      if (!solved.empty() && q == solved)
        return;
      solved.clear();
      simulator.set_design(q);
      simulator.solve_design();
      solved = q;
    };

    const auto  directory      = forma::checkpoint_directory(context);
    auto        stage_settings = settings;
    std::string mesh; // file stem of the current remeshed design, if any
    // Thesis Algorithm 1's outer iteration (a run of L-BFGS on one mesh,
    // from 1) and the iteration it started at.
    unsigned int n_outer = 1, outer_start = 0;
    if (settings.resume)
      {
        const auto place = forma::checkpoint_place(context);
        mesh             = place.mesh;
        n_outer          = place.outer_iteration;
        outer_start      = place.outer_start;
        if (!mesh.empty())
          {
            simulator.load_remeshed(directory + "/" + mesh);
          }
      }
    if (settings.remesh_quality > 0 || settings.element_removal > 0 ||
        settings.outer_iterations > 0)
      for (const auto &b : layout.blocks)
        AssertThrow(!b.on_mesh,
                    dealii::ExcMessage(
                      std::string(settings.element_removal > 0 ?
                                    "Optimization/Element removal" :
                                  settings.remesh_quality > 0 ?
                                    "Optimization/Remesh quality" :
                                    "Optimization/Outer iterations") +
                      ": the design block '" + b.name +
                      "' lives on the mesh and cannot be remeshed."));
    // Algorithm 1's weight schedule: linear over the outer iterations.
    const auto progress = [&]() {
      return settings.outer_iterations > 1 ?
               std::min(1., (n_outer - 1.) / (settings.outer_iterations - 1.)) :
               0.;
    };
    AssertThrow(!simulator.ramp_objective_weights(progress()) ||
                  settings.outer_iterations >= 2,
                dealii::ExcMessage(
                  "Objective/Terms: 'final weight' ramps a weight over thesis "
                  "Algorithm 1's outer iterations: set Optimization/Outer "
                  "iterations to 2 or more."));
    if (settings.element_removal > 0)
      {
        AssertThrow(dim == 2,
                    dealii::ExcMessage(
                      "Optimization/Element removal is available in 2D "
                      "only (in 3D, holes can also pinch along edges)."));
        AssertThrow(
          !simulator[0].holding_boundaries().count(
            settings.element_removal_boundary),
          dealii::ExcMessage(
            "Optimization/Element removal boundary = " +
            std::to_string(settings.element_removal_boundary) +
            " is a support or contact boundary; the holes need a free id."));
      }

    // The constraint's penalty in units of the starting objective.
    double penalty_scale = 0;
    if (constraint && constraint->penalty)
      {
        ensure(simulator.design());
        penalty_scale = std::max(std::abs(simulator.objective()), 1e-300);
      }
    // Hold blocked vertices: per line search (by the iteration it starts
    // from), the shape entries of the cells that made the quality guard
    // reject its last rejected trial; the entries held (gradient zeroed)
    // until the next remesh.
    std::vector<std::pair<std::size_t, std::vector<unsigned int>>> blocked;
    std::set<unsigned int>                                         held;
    unsigned int                                                   n_holds = 0;
    std::size_t n_accepted = 0; // the last accepted iteration
    const auto  guarded    = [&](const std::vector<double> &q) {
      try
        {
          ensure(q);
        }
      catch (...)
        {
          const double threshold = parameters.design.min_scaled_jacobian;
          if (settings.hold_blocked_vertices &&
              simulator.mesh_quality() < threshold)
            {
              // A line search's trials shrink: its last rejected one is
              // the step the guard limits, and names the fewest cells.
              auto entries = simulator.degenerate_shape_entries(threshold);
              if (!blocked.empty() && blocked.back().first == n_accepted)
                blocked.back().second = std::move(entries);
              else
                blocked.emplace_back(n_accepted, std::move(entries));
            }
          throw;
        }
    };
    forma::DesignModel model;
    model.value = [&](const std::vector<double> &q) {
      guarded(q);
      double J = simulator.objective();
      if (penalty_scale > 0)
        {
          std::vector<double> dP(q.size(), 0.);
          J += penalty_scale * constraint->penalty(q, dP);
        }
      return J;
    };
    model.gradient = [&](const std::vector<double> &q,
                         std::vector<double>       &dJ) {
      guarded(q);
      double J = simulator.gradient(dJ);
      if (penalty_scale > 0)
        {
          std::vector<double> dP(q.size(), 0.);
          J += penalty_scale * constraint->penalty(q, dP);
          for (unsigned int i = 0; i < q.size(); ++i)
            dJ[i] += penalty_scale * dP[i];
        }
      // A fresh L-BFGS run never moves an entry whose gradient is zero.
      for (const unsigned int i : held)
        dJ[i] = 0;
      return J;
    };
    nlohmann::json history      = nlohmann::json::array();
    std::string    restart_kind = "remeshed";
    model.accepted =
      [&](const unsigned int k, const std::vector<double> &q, const double J) {
        ensure(q);
        n_accepted = k;
        simulator.write_state(k, context);
        nlohmann::json entry = {{"iteration", k}, {"objective", J}};
        for (const auto &[name, value] : simulator.objective_terms())
          entry["terms"][name] = value;
        nlohmann::json values;
        const auto     text = describe_design(
          layout, model.initial, q, simulator.max_shape_offset(), values);
        if (!values.empty())
          entry["design"] = values;
        if (!text.empty())
          context.log("  design: " + text);
        // The first design after a remesh (or a hold) replaces the last
        // one before.
        if (!history.empty() && history.back()["iteration"] == k)
          {
            entry[restart_kind] = true;
            history.back()      = entry;
          }
        else
          history.push_back(entry);
        context.summary["history"] = history;
      };
    // Remesh when the quality falls below the threshold and clearly below
    // what the last remesh achieved (the boundary, which remeshing keeps,
    // can limit it: remeshing again would not help).
    dealii::Timer wall_timer;
    double        remesh_seconds   = 0;
    bool          remesh_allowed   = settings.remesh_quality > 0;
    bool          removal_done     = false;
    double        remeshed_quality = 1;
    model.remesh_needed            = [&]() {
      const double q = simulator.mesh_quality();
      // The element removal's remesh does not count against the limit.
      const unsigned int n_quality_remeshes =
        simulator.n_remeshes() - (removal_done ? 1 : 0);
      if (!remesh_allowed || n_quality_remeshes >= settings.max_remeshes ||
          (settings.outer_iterations > 0 &&
           n_outer >= settings.outer_iterations) ||
          q >= settings.remesh_quality || q >= remeshed_quality - 0.05)
        return false;
      // Try it first: a remesh that cannot help must not restart L-BFGS.
      std::string   reason;
      dealii::Timer mesh_timer; // Gmsh runs here; remesh() reuses its mesh
      const bool    improves = simulator.remesh_improves(reason);
      remesh_seconds += mesh_timer.wall_time();
      if (improves)
        return true;
      context.print("  no remesh, continuing on the current mesh: " + reason);
      remesh_allowed = false;
      return false;
    };

    // One run of the optimizer per mesh: a remesh ends a run, the next one
    // continues the history on the new mesh.
    const nlohmann::json state0 = [&] {
      ensure(simulator.design());
      return simulator.state_statistics();
    }();
    forma::OptimizationResult result;
    std::vector<double>       history_so_far;
    nlohmann::json            remeshes = nlohmann::json::array();
    nlohmann::json            holds    = nlohmann::json::array();
    // Thesis Table 2.2's columns: the first and last gradient norms, and
    // where the last outer iteration (the run since the last remesh)
    // started.
    double                    first_gradient_norm = 0, last_gradient_norm = 0;
    std::vector<unsigned int> outer_starts{outer_start};
    // J at the end of each finished outer iteration (before its remesh).
    std::vector<double>         outer_last_J;
    std::vector<nlohmann::json> outer_weights; // per outer iteration
    unsigned int                iteration_cap = settings.max_iterations;
    bool outer_possible = true; // false once a remesh failed
    for (;;)
      {
        if (simulator.ramp_objective_weights(progress()) &&
            outer_weights.size() < outer_starts.size())
          {
            solved.clear(); // J changes with the weights
            context.print("[iteration " + std::to_string(outer_start) +
                          "] outer iteration " + std::to_string(n_outer) + "/" +
                          std::to_string(settings.outer_iterations) +
                          ", weights " + ramped_weights(simulator));
          }
        if (outer_weights.size() < outer_starts.size())
          {
            nlohmann::json w = nlohmann::json::object();
            for (const auto &[name, weight] : simulator.ramped_weights())
              w[name] = weight;
            outer_weights.push_back(w);
          }
        stage_settings.max_iterations =
          settings.inner_iterations > 0 ?
            std::min(iteration_cap, outer_start + settings.inner_iterations) :
            iteration_cap;
        stage_settings.outer_iteration = n_outer;
        stage_settings.outer_start     = outer_start;
        model.initial                  = simulator.design();
        model.scale                    = simulator.design_scales(model.initial);
        simulator.design_bounds(model.initial,
                                parameters.design.shape_bound > 0 ?
                                  parameters.design.shape_bound :
                                  std::numeric_limits<double>::infinity(),
                                model.lower,
                                model.upper);
        if (constraint && constraint->setup)
          {
            if constexpr (dim == 2)
              constraint->setup(layout,
                                simulator[0].cell_centers(),
                                model.lower,
                                model.upper);
          }
        model.mesh = mesh;
        result =
          forma::optimize(model, stage_settings, context, history_so_far);
        if (!result.gradient_norms.empty())
          {
            if (first_gradient_norm == 0)
              first_gradient_norm = result.gradient_norms.front();
            last_gradient_norm = result.gradient_norms.back();
          }
        const std::size_t last = result.history.size() - 1;
        // Algorithm 1: a run that stagnated or used its inner iterations
        // is followed by a remesh, unless it lowered J by less than
        // Relative decrease (converged) or the outer iterations are used.
        const bool run_over =
          forma::stagnated(result) ||
          (settings.inner_iterations > 0 &&
           last >= outer_start + settings.inner_iterations &&
           last < iteration_cap);
        const bool converged =
          settings.outer_iterations > 0 && run_over &&
          result.history[outer_start] - result.history[last] <
            settings.relative_decrease * std::abs(result.history.front());
        const bool outer_due = settings.outer_iterations > 0 && run_over &&
                               !converged && outer_possible &&
                               n_outer < settings.outer_iterations;
        if (converged)
          result.stop_reason =
            "Algorithm 1 converged: outer iteration " +
            std::to_string(n_outer) + " lowered J by less than " +
            significant(settings.relative_decrease, 3) + " |J0|";
        if (settings.hold_blocked_vertices && forma::stagnated(result) &&
            n_holds < 10 && !outer_due)
          {
            // The guard blocked the line search in the last window: hold
            // the cells that blocked it and go on with the rest.
            std::set<unsigned int> fresh;
            for (const auto &[k, entries] : blocked)
              if (k + stage_settings.decrease_window >= last)
                for (const unsigned int i : entries)
                  if (!held.count(i))
                    fresh.insert(i);
            blocked.clear();
            if (!fresh.empty())
              {
                held.insert(fresh.begin(), fresh.end());
                ++n_holds;
                ensure(result.design);
                context.print("[iteration " + std::to_string(last) +
                              "] holding " + std::to_string(fresh.size()) +
                              " more shape entries (" +
                              std::to_string(held.size()) +
                              " in all) where the mesh-quality guard blocked "
                              "the line search; going on with the rest");
                holds.push_back(
                  {{"iteration", last}, {"entries", held.size()}});
                history_so_far                       = result.history;
                stage_settings.resume                = false;
                stage_settings.decrease_window_start = last;
                restart_kind                         = "held";
                continue;
              }
          }
        if (result.stop_reason != forma::remesh_stop && !outer_due)
          {
            if (removal_done || settings.element_removal == 0)
              break;
            // The ESO-like step (thesis ch. 2.7.1): drop the low-stress
            // cells of the converged shape, remesh with the holes and
            // optimize on, the volume bound holding the volume left.
            removal_done = true;
            ensure(result.design);
            const std::string at =
              "[iteration " + std::to_string(result.history.size() - 1) + "] ";
            const std::string stem =
              "optimization.mesh_" + std::to_string(result.history.size() - 1);
            std::string line;
            try
              {
                dealii::Timer remesh_timer;
                const auto    removed = forma::select_low_stress_cells(
                  simulator[0].triangulation(),
                  simulator.cell_mean_stress(),
                  settings.element_removal,
                  settings.element_removal_boundary,
                  simulator[0].holding_boundaries());
                if (std::find(removed.begin(), removed.end(), true) ==
                    removed.end())
                  {
                    context.print(at + "element removal: no cell below " +
                                  significant(settings.element_removal, 3) +
                                  " of the largest stress");
                    break;
                  }
                line =
                  simulator.remesh_without(directory + "/" + stem,
                                           removed,
                                           settings.element_removal_boundary);
                remesh_seconds += remesh_timer.wall_time();
              }
            catch (const std::exception &e)
              {
                // The shape-optimized design stands: the remesh fails
                // before it replaces the mesh (Gmsh, quality; the design
                // blocks were checked above).
                line = "element removal failed, keeping the design: " +
                       forma::error_message(e);
                context.print(at + line);
                remeshes.push_back({{"iteration", result.history.size() - 1},
                                    {"description", line},
                                    {"element_removal", false}});
                break;
              }
            mesh = stem;
            held.clear(), blocked.clear(), n_holds = 0;
            restart_kind = "remeshed";
            context.print(at + line);
            solved.clear();
            ensure(simulator.design());
            const double volume = simulator.state_statistics()["volume"];
            simulator.cap_volume_bounds();
            context.print("  volume bounds lowered to the volume left, " +
                          significant(volume, 5));
            remeshes.push_back({{"iteration", result.history.size() - 1},
                                {"description", line},
                                {"element_removal", true},
                                {"volume", volume}});
            history_so_far                       = result.history;
            stage_settings.resume                = false;
            stage_settings.decrease_window_start = result.history.size() - 1;
            outer_last_J.push_back(result.history.back());
            outer_start = result.history.size() - 1, ++n_outer;
            outer_starts.push_back(outer_start);
            // The stage with the holes gets its own iteration budget.
            iteration_cap = result.history.size() - 1 + settings.max_iterations;
            remeshed_quality = simulator.mesh_quality();
            continue;
          }
        ensure(result.design);
        const std::string iteration =
          "[iteration " + std::to_string(result.history.size() - 1) + "] ";
        const std::string next =
          "optimization.mesh_" + std::to_string(result.history.size() - 1);
        std::string        line;
        const unsigned int remeshes_before = simulator.n_remeshes();
        const auto        *mesh_before     = &simulator[0].triangulation();
        try
          {
            dealii::Timer remesh_timer;
            line = simulator.remesh(directory + "/" + next);
            remesh_seconds += remesh_timer.wall_time();
            mesh             = next;
            remeshed_quality = simulator.mesh_quality();
            held.clear(), blocked.clear(), n_holds = 0;
            // J jumps where the new mesh resolves the stress peaks
            // differently: the decrease window restarts on the new mesh.
            stage_settings.decrease_window_start = result.history.size() - 1;
            outer_last_J.push_back(result.history.back());
            outer_start = result.history.size() - 1, ++n_outer;
            outer_starts.push_back(outer_start);
          }
        catch (const std::exception &e)
          {
            // A failure once the mesh is replaced (the reference run of a
            // target objective on the new mesh, say) leaves no valid
            // design to go on with: the run stops with the reason.
            AssertThrow(simulator.n_remeshes() == remeshes_before &&
                          &simulator[0].triangulation() == mesh_before,
                        dealii::ExcMessage(
                          iteration + "the design was remeshed (" + next +
                          ".msh in the output directory) but setting it up "
                          "on the new mesh failed: " +
                          forma::error_message(e)));
            // The current mesh is still valid: go on without remeshing.
            line = "remeshing failed, continuing on the current mesh: " +
                   forma::error_message(e);
            remesh_allowed = false;
            outer_possible = false;
          }
        context.print(iteration + line);
        remeshes.push_back(
          {{"iteration", result.history.size() - 1}, {"description", line}});
        solved.clear();
        history_so_far        = result.history;
        stage_settings.resume = false;
        restart_kind          = "remeshed";
      }

    const double J0 = result.history.front(), J1 = result.history.back();
    context.print("stopped after " + std::to_string(result.history.size() - 1) +
                  " iterations: " + result.stop_reason);
    const double relative_gradient_norm =
      first_gradient_norm > 0 ? last_gradient_norm / first_gradient_norm : 0;
    const double last_outer_reduction =
      outer_start < result.history.size() ?
        100 * (result.history[outer_start] - J1) / std::abs(J0) :
        0;
    // Per outer iteration: where it started, its weights and what it
    // lowered J by on its own mesh and weights (its first value to its
    // last, before the remesh).
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
            100 * (result.history[outer_starts[i]] - last_J) / std::abs(J0)}});
      }
    context.log("outer iterations (meshes) " + std::to_string(n_outer) +
                ", relative gradient norm " +
                significant(relative_gradient_norm, 3) +
                ", the last one's reduction of J " +
                significant(last_outer_reduction, 3) + "% of J0");
    context.print("objective " + significant(J0, 6) + " -> " +
                  significant(J1, 6) + " (ratio " + significant(J1 / J0, 4) +
                  ")");
    ensure(result.design);
    const nlohmann::json state1 = simulator.state_statistics();
    for (const auto &[key, label] :
         {std::pair<std::string, std::string>{"max_stress",
                                              "max stress (Frobenius)"},
          {"max_von_mises_stress", "max von Mises stress"},
          {"volume", "volume"}})
      context.print(label + " " + significant(double(state0[key]), 5) + " -> " +
                    significant(double(state1[key]), 5) + " (ratio " +
                    significant(double(state1[key]) / double(state0[key]), 4) +
                    ")");
    nlohmann::json final_values;
    const auto     text = describe_design(layout,
                                      model.initial,
                                      result.design,
                                      simulator.max_shape_offset(),
                                      final_values);
    if (!text.empty())
      context.print("final design: " + text);
    context.summary["optimization"] = {
      {"initial_objective", J0},
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
      {"outer", outer},
      {"relative_gradient_norm", relative_gradient_norm},
      {"last_outer_reduction_percent", last_outer_reduction},
      {"final_design", final_values}};
    context.summary["adjoint"] = simulator.adjoint_statistics();
    {
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
    }
    // The key numbers at the top level (thesis Table 2.2 columns).
    context.summary["initial_objective"]  = J0;
    context.summary["final_objective"]    = J1;
    context.summary["initial_max_stress"] = state0["max_stress"];
    context.summary["final_max_stress"]   = state1["max_stress"];
    context.summary["initial_volume"]     = state0["volume"];
    context.summary["final_volume"]       = state1["volume"];
    if (context.is_root())
      {
        std::ofstream csv(context.path("history.csv"));
        csv << "iteration,objective\n";
        for (unsigned int k = 0; k < result.history.size(); ++k)
          csv << k << ',' << std::setprecision(12) << result.history[k] << '\n';
        forma::write_history_plot(context.path("convergence.png"),
                                  result.history,
                                  "objective history",
                                  "iteration",
                                  {outer_starts.begin() + 1,
                                   outer_starts.end()},
                                  "remesh (new outer iteration)");
      }
    return result.design;
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
