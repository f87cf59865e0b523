// Mode = optimize of the elasticity apps: thesis Algorithm 1 around the
// optimizer. One L-BFGS run per mesh; a run ends in a remesh (mesh quality,
// or an outer iteration), a hold of the vertices that block the line
// search, an element removal, or the end.

#include "optimize_job.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/timer.h>

#include <forma/adjoint/objective.h>
#include <forma/base/plot.h>
#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/elasticity/element_removal.h>
#include <forma/elasticity/load_cases.h>
#include <forma/elasticity/simulator.h>

#include "volume_minimization.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <set>
#include <sstream>

namespace forma
{
  namespace
  {
    std::string
    at_iteration(const std::size_t k)
    {
      return "[iteration " + std::to_string(k) + "] ";
    }

    // Values of the small (non-shape) design blocks, e.g. recovered
    // materials.
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



    template <int dim>
    class OptimizeJob
    {
    public:
      OptimizeJob(const ElasticityParameters   &parameters,
                  const OptimizationParameters &settings,
                  RunContext                   &context,
                  const DesignConstraint       *constraint);

      std::vector<double>
      run();

    private:
      // Set-up.
      void
      resume();
      void
      check_settings();
      void
      connect_model();

      // The optimizer's callbacks.
      void
      ensure(const std::vector<double> &q);
      void
      guarded(const std::vector<double> &q);
      double
      penalized(const std::vector<double> &q, std::vector<double> *dJ);
      void
      accepted(const unsigned int         k,
               const std::vector<double> &q,
               const double               J);
      bool
      remesh_needed();

      // Algorithm 1's loop.
      double
      progress() const;
      unsigned int
      inner_iterations() const;
      void
      start_run();
      bool
      hold_blocked();
      bool
      remove_elements();
      void
      remesh_and_restart();
      void
      refine_and_restart();
      void
      begin_outer_iteration(const std::size_t last);
      void
      solve_on_new_mesh();
      bool
      roll_back(const unsigned int n_before);
      void
      restart(const std::string &kind);
      void
      run_stage();
      void
      start_volume_stage();
      void
      set_stage_objective();
      double
      scaled_gradient_norm(const std::vector<double> &q);
      double
      stress_norm(const KeyValueRecord &stress) const;

      // The results.
      void
      report();
      double
      relative_gradient_norm() const;
      double
      last_outer_reduction() const;
      std::string
      objective_line() const;
      void
      print_results(const nlohmann::json &state1,
                    const std::string    &design_text) const;
      void
      write_summary(const nlohmann::json &state1,
                    const nlohmann::json &final_values);
      nlohmann::json
      outer_summary() const;
      void
      write_history() const;

      const ElasticityParameters   &parameters;
      const OptimizationParameters &settings;
      RunContext                   &context;
      const DesignConstraint       *constraint;
      LoadCases<dim>                simulator;
      dealii::Timer                 wall_timer;

      /// The design the simulator last solved (empty: none).
      std::vector<double>    solved;
      DesignModel            model;
      OptimizationParameters stage_settings;
      const std::string      directory;
      /// File stem of the current remeshed design, if any.
      std::string mesh;
      /// Thesis Algorithm 1's outer iteration (a run of L-BFGS on one mesh,
      /// from 1) and the iteration it started at.
      unsigned int n_outer = 1, outer_start = 0;
      /// The constraint's penalty in units of the starting objective.
      double penalty_scale = 0;

      // Hold blocked vertices: per line search (by the iteration it starts
      // from), the shape entries of the cells that made the quality guard
      // reject its last rejected trial; the entries held (gradient zeroed)
      // until the next remesh.
      std::vector<std::pair<std::size_t, std::vector<unsigned int>>> blocked;
      std::set<unsigned int>                                         held;
      unsigned int n_holds    = 0;
      std::size_t  n_accepted = 0; ///< the last accepted iteration

      nlohmann::json history          = nlohmann::json::array();
      std::string    restart_kind     = "remeshed";
      double         remesh_seconds   = 0;
      bool           remesh_allowed   = false;
      bool           removal_done     = false;
      bool           outer_possible   = true; ///< false once a remesh failed
      double         remeshed_quality = 1;

      nlohmann::json      state0;
      OptimizationResult  result;
      std::vector<double> history_so_far;
      nlohmann::json      remeshes = nlohmann::json::array();
      nlohmann::json      holds    = nlohmann::json::array();
      // Thesis Table 2.2's columns: the first and last gradient norms, and
      // where the last outer iteration (the run since the last remesh)
      // started.
      double                    first_gradient_norm = 0, last_gradient_norm = 0;
      std::vector<unsigned int> outer_starts;
      /// J at the end of each finished outer iteration (before its remesh).
      std::vector<double>         outer_last_J;
      std::vector<nlohmann::json> outer_weights; ///< per outer iteration
      unsigned int                iteration_cap;

      /// The volume stage's Objective/Terms (empty: the stress stage) and
      /// the iteration it started at; the state there.
      std::string    stage_terms;
      unsigned int   stage_start = 0;
      nlohmann::json stage_start_state;
      /// The stress stage's last J and why it stopped (unknown to a run
      /// resumed in the volume stage).
      double      stress_stage_J = std::numeric_limits<double>::quiet_NaN();
      std::string stress_stage_stop;
    };



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
      stage_terms = place.stage_terms;
      stage_start = place.stage_start;
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
      // before.
      if (!history.empty() && history.back()["iteration"] == k)
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
    // remesh failed (it goes on on its mesh), run on to their end.
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
            constraint->setup(simulator.design_layout(),
                              simulator[0].cell_centers(),
                              model.lower,
                              model.upper);
        }
      model.mesh = mesh;
    }



    // The guard blocked the line search in the last window: hold the cells
    // that blocked it and go on with the rest. False: nothing new to hold.
    template <int dim>
    bool
    OptimizeJob<dim>::hold_blocked()
    {
      const std::size_t      last = result.history.size() - 1;
      std::set<unsigned int> fresh;
      for (const auto &[k, entries] : blocked)
        if (k + stage_settings.decrease_window >= last)
          for (const unsigned int i : entries)
            if (!held.count(i))
              fresh.insert(i);
      blocked.clear();
      if (fresh.empty())
        return false;
      held.insert(fresh.begin(), fresh.end());
      ++n_holds;
      ensure(result.design);
      context.print(at_iteration(last) + "holding " +
                    std::to_string(fresh.size()) + " more shape entries (" +
                    std::to_string(held.size()) +
                    " in all) where the mesh-quality guard blocked the line "
                    "search; going on with the rest");
      holds.push_back({{"iteration", last}, {"entries", held.size()}});
      stage_settings.decrease_window_start = last;
      restart("held");
      return true;
    }



    // The ESO-like step (thesis ch. 2.7.1): drop the low-stress cells of
    // the converged shape, remesh with the holes and optimize on, the
    // volume bound holding the volume left. False: the run ends.
    template <int dim>
    bool
    OptimizeJob<dim>::remove_elements()
    {
      removal_done = true;
      ensure(result.design);
      const std::size_t  last = result.history.size() - 1;
      const std::string  at   = at_iteration(last);
      const std::string  stem = "optimization.mesh_" + std::to_string(last);
      std::string        line;
      const unsigned int n_before = simulator.n_remeshes();
      try
        {
          dealii::Timer remesh_timer;
          const auto    removed =
            select_low_stress_cells(simulator[0].triangulation(),
                                    simulator.cell_mean_stress(),
                                    settings.element_removal,
                                    settings.element_removal_boundary,
                                    simulator[0].holding_boundaries());
          if (std::find(removed.begin(), removed.end(), true) == removed.end())
            {
              context.print(at + "element removal: no cell below " +
                            sig(settings.element_removal, 3) +
                            " of the largest stress");
              return false;
            }
          line = simulator.remesh_without(directory + "/" + stem,
                                          removed,
                                          settings.element_removal_boundary);
          remesh_seconds += remesh_timer.wall_time();
          solve_on_new_mesh();
        }
      catch (const std::exception &e)
        {
          // The shape-optimized design stands, on its mesh.
          if (!roll_back(n_before))
            throw;
          line =
            "element removal failed, keeping the design: " + error_message(e);
          context.print(at + line);
          remeshes.push_back({{"iteration", last},
                              {"description", line},
                              {"element_removal", false}});
          return false;
        }
      mesh = stem;
      context.print(at + line);
      const double volume = simulator.state_statistics()["volume"];
      simulator.cap_volume_bounds();
      context.print("  volume bounds lowered to the volume left, " +
                    sig(volume, 5));
      remeshes.push_back({{"iteration", last},
                          {"description", line},
                          {"element_removal", true},
                          {"volume", volume}});
      begin_outer_iteration(last);
      // The stage with the holes gets its own iteration budget.
      iteration_cap    = last + settings.max_iterations;
      remeshed_quality = simulator.mesh_quality();
      restart("remeshed");
      return true;
    }



    // Remesh the design (mesh quality, or the next outer iteration); if that
    // fails, go on without remeshing.
    template <int dim>
    void
    OptimizeJob<dim>::remesh_and_restart()
    {
      ensure(result.design);
      const std::size_t  last = result.history.size() - 1;
      const std::string  next = "optimization.mesh_" + std::to_string(last);
      std::string        line;
      const unsigned int n_before = simulator.n_remeshes();
      try
        {
          dealii::Timer remesh_timer;
          line = simulator.remesh(directory + "/" + next);
          remesh_seconds += remesh_timer.wall_time();
          solve_on_new_mesh();
          mesh             = next;
          remeshed_quality = simulator.mesh_quality();
          begin_outer_iteration(last);
        }
      catch (const std::exception &e)
        {
          // Gmsh, the quality check, the reference run of a target
          // objective or the solve on the new mesh failed: go on with the
          // design on the mesh it was found on, without remeshing.
          if (!roll_back(n_before))
            throw;
          line = "remeshing failed, continuing on the current mesh: " +
                 error_message(e);
          remesh_allowed = false;
          outer_possible = false;
        }
      context.print(at_iteration(last) + line);
      remeshes.push_back({{"iteration", last}, {"description", line}});
      restart("remeshed");
    }



    // A new mesh (remeshed, refined, with holes) after iteration `last`:
    // the next outer iteration. J jumps where the new mesh resolves the
    // stress differently, so the decrease window restarts; the new DoFs
    // release held vertices.
    template <int dim>
    void
    OptimizeJob<dim>::begin_outer_iteration(const std::size_t last)
    {
      held.clear(), blocked.clear(), n_holds = 0;
      stage_settings.decrease_window_start = last;
      outer_last_J.push_back(result.history.back());
      outer_start = last, ++n_outer;
      outer_starts.push_back(outer_start);
    }



    // The next outer iteration on the mesh refined for the current design
    // (Outer step = refine); the design is carried over.
    template <int dim>
    void
    OptimizeJob<dim>::refine_and_restart()
    {
      ensure(result.design);
      const std::size_t  last = result.history.size() - 1;
      const std::string  next = "optimization.mesh_" + std::to_string(last);
      dealii::Timer      refine_timer;
      std::string        line;
      const unsigned int refinements = simulator[0].n_refinements();
      const double       before      = simulator.objective();
      try
        {
          line = simulator.refine_design(directory + "/" + next);
        }
      catch (const std::exception &e)
        {
          // Refused before the mesh changed: on without outer steps.
          if (simulator[0].n_refinements() != refinements)
            throw;
          solved.clear(); // an indicator may have solved other states
          line =
            "not refined, continuing on the current mesh: " + error_message(e);
          context.print(at_iteration(last) + line);
          remeshes.push_back({{"iteration", last}, {"description", line}});
          outer_possible = false;
          restart("refined");
          return;
        }
      remesh_seconds += refine_timer.wall_time();
      solve_on_new_mesh();
      mesh = next;
      begin_outer_iteration(last);
      context.print(at_iteration(last) + line);
      // J of the same design before and after: the discretization error
      // the refinement removed.
      remeshes.push_back({{"iteration", last},
                          {"description", line},
                          {"refinement", true},
                          {"n_dofs", simulator[0].n_dofs()},
                          {"objective_before", before},
                          {"objective_after", simulator.objective()}});
      restart("refined");
    }



    // After a failed remesh: back to the mesh (and design) the design was
    // found on. False if a new mesh was kept already and cannot be undone.
    template <int dim>
    bool
    OptimizeJob<dim>::roll_back(const unsigned int n_before)
    {
      solved.clear();
      return simulator.undo_remesh() || simulator.n_remeshes() == n_before;
    }



    // A new mesh is kept only once the design solves on it; otherwise the
    // caller undoes the remesh (roll_back()).
    template <int dim>
    void
    OptimizeJob<dim>::solve_on_new_mesh()
    {
      solved.clear();
      ensure(simulator.design());
      simulator.commit_remesh();
    }



    // The next L-BFGS run continues the history so far; `kind` marks its
    // first entry in the summary's history.
    template <int dim>
    void
    OptimizeJob<dim>::restart(const std::string &kind)
    {
      history_so_far        = result.history;
      stage_settings.resume = false;
      restart_kind          = kind;
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
  } // namespace



  template <int dim>
  std::vector<double>
  optimize_job(const ElasticityParameters   &parameters,
               const OptimizationParameters &settings,
               RunContext                   &context,
               const DesignConstraint       *constraint)
  {
    return OptimizeJob<dim>(parameters, settings, context, constraint).run();
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
