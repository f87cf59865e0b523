// Mode = optimize of the elasticity apps: thesis Algorithm 1 around the
// optimizer. One L-BFGS run per mesh; a run ends in a remesh (mesh quality,
// or an outer iteration), a hold of the vertices that block the line
// search, an element removal, or the end. This file: the set-up, the
// optimizer's callbacks, the loop and the volume stage; the steps between
// runs are in optimize_job_outer.cc, the results in optimize_job_report.cc.

#include "optimize_job.h"

#include <deal.II/base/exceptions.h>

#include <forma/adjoint/objective.h>
#include <forma/base/application.h>
#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/elasticity/load_cases.h>
#include <forma/elasticity/simulator.h>

#include "optimize_job_impl.h"
#include "volume_minimization.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace forma
{
  namespace
  {
    // "name w, ..." of the terms whose weights ramp (thesis Algorithm 1).
    template <int dim>
    std::string
    ramped_weights(const LoadCases<dim> &simulator)
    {
      std::string text;
      for (const auto &[name, weight] : simulator.ramped_weights())
        text += (text.empty() ? "" : ", ") + name + " " + sig(weight, 4);
      return text;
    }
  } // namespace



  namespace internal
  {
    template <int dim>
    OptimizeJob<dim>::OptimizeJob(const ElasticityParameters   &parameters,
                                  const OptimizationParameters &settings,
                                  RunContext                   &context,
                                  const DesignConstraint       *constraint)
      : parameters(parameters)
      , settings(settings)
      , context(context)
      , constraint(constraint)
      , simulator(parameters, context.communicator())
      , stage_settings(settings)
      , directory(checkpoint_directory(context))
      , remesh_allowed(settings.remesh_quality > 0)
      , iteration_cap(settings.max_iterations)
    {
      simulator.prepare(&context);
      AssertThrow(simulator.design_layout().size() > 0,
                  dealii::ExcMessage("Design/Parameters is empty: there is "
                                     "nothing to optimize."));
      simulator.set_objective(parameters.objective);
      if (simulator.n_cases() > 1)
        context.print(std::to_string(simulator.n_cases()) +
                      " load cases; VTU frames show the first");
      if (settings.resume)
        resume();
      if (outer_starts.empty() || outer_starts.back() != outer_start)
        outer_starts.push_back(outer_start);
      check_settings();
      if (constraint && constraint->penalty)
        {
          ensure(simulator.design());
          penalty_scale = std::max(std::abs(simulator.objective()), 1e-300);
        }
      if (!stage_terms.empty()) // resumed in the volume stage
        set_stage_objective();
      connect_model();
      wall_timer.restart(); // the optimization's time, after the set-up
      ensure(simulator.design());
      state0 = simulator.state_statistics();
    }



    template <int dim>
    void
    OptimizeJob<dim>::resume()
    {
      const auto place = checkpoint_place(context);
      mesh             = place.mesh;
      n_outer          = place.outer_iteration;
      outer_start      = place.outer_start;
      if (!mesh.empty() && settings.outer_step == "refine")
        simulator.load_refinement(directory + "/" + mesh);
      else if (!mesh.empty())
        {
          simulator.load_remeshed(directory + "/" + mesh);
          simulator.commit_remesh();
        }
      stage_terms         = place.stage_terms;
      stage_start         = place.stage_start;
      first_gradient_norm = place.first_gradient_norm;
      // A resumed run does not retry a remesh that failed.
      outer_possible = place.outer_possible;
      remesh_allowed &= outer_possible;
      if (!place.records.empty())
        try
          {
            restore_records(nlohmann::json::parse(place.records),
                            place.iteration);
          }
        catch (const std::exception &e)
          {
            AssertThrow(false,
                        dealii::ExcMessage(
                          "Optimization/Resume: the records in '" + directory +
                          "/optimization.checkpoint.json' are unreadable: " +
                          error_message(e)));
          }
    }



    // What the summary reports of the iterations before the checkpoint.
    template <int dim>
    std::string
    OptimizeJob<dim>::records() const
    {
      return nlohmann::json{{"history", history},
                            {"remeshes", remeshes},
                            {"holds", holds},
                            {"outer_starts", outer_starts},
                            {"outer_last_J", outer_last_J},
                            {"outer_weights", outer_weights}}
        .dump();
    }



    // The current outer iteration's weights are left to start_run(), which
    // ramps them (and clears the solves made with the old ones) as at the
    // start of any outer iteration. An element removal before the
    // checkpoint is not done again, and the stage after it keeps its own
    // iteration budget.
    template <int dim>
    void
    OptimizeJob<dim>::restore_records(const nlohmann::json &r,
                                      const unsigned int    iteration)
    {
      for (const auto &entry : r.at("history"))
        if (entry.at("iteration").get<unsigned int>() <= iteration)
          history.push_back(entry);
      remeshes      = r.at("remeshes");
      holds         = r.at("holds");
      outer_starts  = r.at("outer_starts").get<std::vector<unsigned int>>();
      outer_last_J  = r.at("outer_last_J").get<std::vector<double>>();
      outer_weights = r.at("outer_weights").get<std::vector<nlohmann::json>>();
      if (!outer_weights.empty() && outer_weights.size() == outer_starts.size())
        outer_weights.pop_back();
      for (const auto &remesh : remeshes)
        if (remesh.value("element_removal", false))
          {
            removal_done  = true;
            iteration_cap = remesh.at("iteration").get<unsigned int>() +
                            settings.max_iterations;
          }
      resumed_iteration = iteration;
    }



    template <int dim>
    void
    OptimizeJob<dim>::check_settings()
    {
      const bool refine = settings.outer_step == "refine";
      if (refine)
        {
          AssertThrow(parameters.adaptivity == "h" &&
                        parameters.problem == "static",
                      dealii::ExcMessage(
                        "Optimization/Outer step = refine: needs Finite "
                        "element/Adaptivity = h (its Error indicator and "
                        "Refine fraction say where) and a static problem."));
          AssertThrow(simulator.n_cases() == 1 ||
                        parameters.adaptive_cycles == 0,
                      dealii::ExcMessage(
                        "Optimization/Outer step = refine with several load "
                        "cases refines one mesh for all: set Finite "
                        "element/Adaptive cycles = 0 (each case would adapt "
                        "its own)."));
          simulator.guard_cell_corners(true); // designs stay refinable
        }
      if (settings.remesh_quality > 0 || settings.element_removal > 0 ||
          settings.outer_iterations > 0)
        for (const auto &b : simulator.design_layout().blocks)
          AssertThrow(!b.on_mesh || (refine && b.per_cell > 0),
                      dealii::ExcMessage(
                        std::string(settings.element_removal > 0 ?
                                      "Optimization/Element removal" :
                                    settings.remesh_quality > 0 ?
                                      "Optimization/Remesh quality" :
                                    refine ?
                                      "Optimization/Outer step = refine" :
                                      "Optimization/Outer iterations") +
                        ": the design block '" + b.name +
                        (refine ? "' lives on the mesh's DoFs and is not "
                                  "carried over a refinement." :
                                  "' lives on the mesh and cannot be "
                                  "remeshed.")));
      AssertThrow(
        !simulator.ramp_objective_weights(progress()) ||
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
      if (settings.volume_minimization > 0)
        {
          AssertThrow(simulator.n_cases() == 1,
                      dealii::ExcMessage(
                        "Optimization/Volume minimization iterations: the "
                        "stage holds the stress of one load case; clear "
                        "Boundary conditions/Load cases."));
          stress_term_of(parameters.objective.terms);
        }
    }



    template <int dim>
    void
    OptimizeJob<dim>::connect_model()
    {
      model.value = [this](const std::vector<double> &q) {
        return penalized(q, nullptr);
      };
      model.gradient = [this](const std::vector<double> &q,
                              std::vector<double>       &dJ) {
        return penalized(q, &dJ);
      };
      model.accepted      = [this](const unsigned int         k,
                              const std::vector<double> &q,
                              const double J) { accepted(k, q, J); };
      model.remesh_needed = [this]() { return remesh_needed(); };
      model.records       = [this]() { return records(); };
    }



    // The simulator keeps the last solved design; solve only when q moves.
    template <int dim>
    void
    OptimizeJob<dim>::ensure(const std::vector<double> &q)
    {
      if (!solved.empty() && q == solved)
        return;
      solved.clear();
      simulator.set_design(q);
      simulator.solve_design();
      solved = q;
    }



    template <int dim>
    void
    OptimizeJob<dim>::guarded(const std::vector<double> &q)
    {
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
    }



    // J (and its gradient, if dJ is given) with the constraint's penalty.
    template <int dim>
    double
    OptimizeJob<dim>::penalized(const std::vector<double> &q,
                                std::vector<double>       *dJ)
    {
      guarded(q);
      double J = dJ ? simulator.gradient(*dJ) : simulator.objective();
      if (penalty_scale > 0)
        {
          std::vector<double> dP(q.size(), 0.);
          J += penalty_scale * constraint->penalty(q, dP);
          if (dJ)
            for (unsigned int i = 0; i < q.size(); ++i)
              (*dJ)[i] += penalty_scale * dP[i];
        }
      // A fresh L-BFGS run never moves an entry whose gradient is zero.
      if (dJ)
        for (const unsigned int i : held)
          (*dJ)[i] = 0;
      return J;
    }



    template <int dim>
    void
    OptimizeJob<dim>::accepted(const unsigned int         k,
                               const std::vector<double> &q,
                               const double               J)
    {
      ensure(q);
      n_accepted = k;
      simulator.write_state(k, context);
      nlohmann::json entry = {{"iteration", k}, {"objective", J}};
      for (const auto &[name, value] : simulator.objective_terms())
        entry["terms"][name] = value;
      nlohmann::json values;
      const auto     text = describe_design(simulator.design_layout(),
                                        model.initial,
                                        q,
                                        simulator.max_shape_offset(),
                                        values);
      if (!values.empty())
        entry["design"] = values;
      if (!text.empty())
        context.log("  design: " + text);
      // The first design after a remesh (or a hold) replaces the last one
      // before; a resumed job keeps the interrupted run's entry.
      if (static_cast<int>(k) == resumed_iteration && !history.empty() &&
          history.back()["iteration"] == k)
        resumed_iteration = -1;
      else if (!history.empty() && history.back()["iteration"] == k)
        {
          entry[restart_kind] = true;
          history.back()      = entry;
        }
      else
        history.push_back(entry);
      context.summary["history"] = history;
    }



    // Remesh when the quality falls below the threshold and clearly below
    // what the last remesh achieved (the boundary, which remeshing keeps,
    // can limit it: remeshing again would not help).
    template <int dim>
    bool
    OptimizeJob<dim>::remesh_needed()
    {
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
    }



    // Algorithm 1's weight schedule: linear over the outer iterations.
    template <int dim>
    double
    OptimizeJob<dim>::progress() const
    {
      return settings.outer_iterations > 1 ?
               std::min(1., (n_outer - 1.) / (settings.outer_iterations - 1.)) :
               0.;
    }



    // Algorithm 1's inner iterations; the volume stage, and a run whose
    // remesh failed or whose refinement was refused (it goes on on its
    // mesh), run on to their end.
    template <int dim>
    unsigned int
    OptimizeJob<dim>::inner_iterations() const
    {
      return stage_terms.empty() && outer_possible ? settings.inner_iterations :
                                                     0;
    }



    // The weights, iteration budget and bounds of the next L-BFGS run.
    template <int dim>
    void
    OptimizeJob<dim>::start_run()
    {
      if (simulator.ramp_objective_weights(progress()) &&
          outer_weights.size() < outer_starts.size())
        {
          solved.clear(); // J changes with the weights
          context.print(at_iteration(outer_start) + "outer iteration " +
                        std::to_string(n_outer) + "/" +
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
        inner_iterations() > 0 ?
          std::min(iteration_cap, outer_start + inner_iterations()) :
          iteration_cap;
      stage_settings.outer_iteration     = n_outer;
      stage_settings.outer_possible      = outer_possible;
      stage_settings.outer_start         = outer_start;
      stage_settings.first_gradient_norm = first_gradient_norm;
      model.initial                      = simulator.design();
      model.scale = simulator.design_scales(model.initial);
      simulator.design_bounds(model.initial,
                              parameters.design.shape_bound > 0 ?
                                parameters.design.shape_bound :
                                std::numeric_limits<double>::infinity(),
                              model.lower,
                              model.upper);
      if (constraint && constraint->setup)
        {
          if constexpr (dim == 2)
            constraint->setup(simulator.design_layout(),
                              simulator[0].cell_centers(),
                              model.lower,
                              model.upper);
        }
      model.mesh = mesh;
    }



    template <int dim>
    std::vector<double>
    OptimizeJob<dim>::run()
    {
      if (stage_terms.empty())
        {
          run_stage();
          if (settings.volume_minimization > 0)
            start_volume_stage();
        }
      if (!stage_terms.empty())
        {
          iteration_cap = stage_start + settings.volume_minimization;
          run_stage();
        }
      report();
      return result.design;
    }



    // Algorithm 1 on the current objective, until it stops.
    template <int dim>
    void
    OptimizeJob<dim>::run_stage()
    {
      for (;;)
        {
          start_run();
          result = optimize(model, stage_settings, context, history_so_far);
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
            stagnated(result) ||
            (inner_iterations() > 0 &&
             last >= outer_start + inner_iterations() && last < iteration_cap);
          const bool converged =
            settings.outer_iterations > 0 && run_over &&
            result.history[outer_start] - result.history[last] <
              settings.relative_decrease * std::abs(result.history.front());
          const bool outer_due = settings.outer_iterations > 0 && run_over &&
                                 !converged && outer_possible &&
                                 n_outer < settings.outer_iterations;
          if (converged)
            result.stop_reason = "Algorithm 1 converged: outer iteration " +
                                 std::to_string(n_outer) +
                                 " lowered J by less than " +
                                 sig(settings.relative_decrease, 3) + " |J0|";
          if (settings.hold_blocked_vertices && stagnated(result) &&
              n_holds < 10 && !outer_due && hold_blocked())
            continue;
          if (result.stop_reason != remesh_stop && !outer_due)
            {
              if (removal_done || settings.element_removal == 0 ||
                  !remove_elements())
                break;
              continue;
            }
          if (settings.outer_step == "refine")
            refine_and_restart();
          else
            remesh_and_restart();
        }
    }



    // Thesis Table 2.2's "Post vol. min.": from the stress-optimized design,
    // minimize the volume with the stress norm held (volume_minimization.h).
    template <int dim>
    void
    OptimizeJob<dim>::start_volume_stage()
    {
      const std::size_t last = result.history.size() - 1;
      ensure(result.design);
      simulator.objective(); // the terms' values at this design
      stage_start_state  = simulator.state_statistics();
      stress_stage_J     = result.history.back();
      stress_stage_stop  = result.stop_reason;
      const auto  stress = stress_term_of(parameters.objective.terms);
      VolumeStage v;
      v.J0        = std::abs(result.history.front());
      v.norm      = stress_norm(stress);
      v.hold_peak = settings.volume_minimization_bound == "peak";
      v.slack     = settings.volume_minimization_slack;
      v.weight    = settings.volume_minimization_weight;
      // Per material where the term has one and the mesh several.
      const auto of_material = [&](const std::string &key,
                                   const std::string &by_material) {
        const auto m = std::to_string(int(stress.key("material", -1.)));
        return stage_start_state.contains(by_material) &&
                   stage_start_state[by_material].contains(m) ?
                 stage_start_state[by_material][m].get<double>() :
                 stage_start_state[key].get<double>();
      };
      v.V1   = of_material("volume", "volume_by_material");
      v.peak = stress.name == "stress" ?
                 of_material("max_stress", "max_stress_by_material") :
                 stage_start_state["max_von_mises_stress"].get<double>();
      // The stage is an outer iteration of its own (summary, plot).
      outer_last_J.push_back(result.history.back());
      outer_start = last, ++n_outer;
      outer_starts.push_back(outer_start);
      // The volume is nearly linear in the shape, so L-BFGS finds no
      // curvature and would creep along the gradient: scale the stage's
      // objective so that its first step is as long as the first stage's
      // (with Normalize objective, ROL divides the scale out again).
      stage_start = last;
      stage_terms = volume_minimization_terms(parameters.objective.terms, v);
      set_stage_objective();
      const double g = scaled_gradient_norm(result.design);
      v.scale = g > 0 && first_gradient_norm > 0 ? first_gradient_norm / g : 1.;
      stage_terms = volume_minimization_terms(parameters.objective.terms, v);
      set_stage_objective();
      context.print(
        at_iteration(last) +
        "volume minimization with the stress held, terms: " + stage_terms);
      stage_settings.decrease_window_start = last;
      restart("volume minimization");
    }



    // The unweighted value of the stress term `stress` now.
    template <int dim>
    double
    OptimizeJob<dim>::stress_norm(const KeyValueRecord &stress) const
    {
      double weighted = 0, weight = stress.key("weight", 1.);
      for (const auto &[name, value] : simulator.objective_terms())
        if (name == stress.name)
          weighted = value;
      for (const auto &[name, w] : simulator.ramped_weights())
        if (name == stress.name)
          weight = w;
      return weighted / weight;
    }



    // |dJ/dz| at q in the optimizer's variables z (q = q0 + scale z).
    template <int dim>
    double
    OptimizeJob<dim>::scaled_gradient_norm(const std::vector<double> &q)
    {
      ensure(q);
      std::vector<double> dJ;
      simulator.gradient(dJ);
      const auto scale = simulator.design_scales(q);
      double     norm  = 0;
      for (unsigned int i = 0; i < dJ.size(); ++i)
        norm += std::pow(scale[i] * dJ[i], 2);
      return std::sqrt(norm);
    }



    template <int dim>
    void
    OptimizeJob<dim>::set_stage_objective()
    {
      ObjectiveParameters objective = parameters.objective;
      objective.terms               = stage_terms;
      simulator.set_objective(objective);
      simulator.ramp_objective_weights(progress());
      solved.clear();
      stage_settings.stage_terms = stage_terms;
      stage_settings.stage_start = stage_start;
    }



    template class OptimizeJob<2>;
    template class OptimizeJob<3>;
  } // namespace internal



  template <int dim>
  std::vector<double>
  optimize_job(const ElasticityParameters   &parameters,
               const OptimizationParameters &settings,
               RunContext                   &context,
               const DesignConstraint       *constraint)
  {
    return internal::OptimizeJob<dim>(parameters, settings, context, constraint)
      .run();
  }

  template std::vector<double>
  optimize_job<2>(const ElasticityParameters &,
                  const OptimizationParameters &,
                  RunContext &,
                  const DesignConstraint *);
  template std::vector<double>
  optimize_job<3>(const ElasticityParameters &,
                  const OptimizationParameters &,
                  RunContext &,
                  const DesignConstraint *);
} // namespace forma
