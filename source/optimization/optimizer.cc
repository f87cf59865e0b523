#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <forma/base/application.h>
#include <forma/base/replace_file.h>
#include <forma/base/run_context.h>
#include <forma/optimization/optimizer.h>

#include "secant_memory.h"
#include <ROL_Algorithm.hpp>
#include <ROL_Bounds.hpp>
#include <ROL_CombinedStatusTest.hpp>
#include <ROL_LineSearchStep.hpp>
#include <ROL_Objective.hpp>
#include <ROL_SecantFactory.hpp>
#include <ROL_StatusTest.hpp>
#include <ROL_StdVector.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace forma
{
  namespace
  {
    // The stagnation stops (see stagnated()).
    const std::string step_vanished          = "the step vanished";
    const std::string rol_stopped            = "ROL stopped";
    const std::string relative_decrease_stop = "relative decrease below ";
  } // namespace



  bool
  stagnated(const OptimizationResult &result)
  {
    return result.stop_reason == step_vanished ||
           result.stop_reason == rol_stopped ||
           result.stop_reason.rfind(relative_decrease_stop, 0) == 0;
  }



  using namespace dealii;

  void
  OptimizationParameters::declare(ParameterHandler &prm)
  {
    prm.enter_subsection("Optimization");
    prm.declare_entry("Max iterations",
                      "50",
                      Patterns::Integer(0),
                      "Accepted L-BFGS iterations at most.");
    prm.declare_entry("Relative decrease",
                      "1e-3",
                      Patterns::Double(0),
                      "epsilon_r of thesis ch. 2.5: stop when J fell by less "
                      "than this times |J0| over 'Decrease window' "
                      "iterations.");
    prm.declare_entry("Decrease window",
                      "2",
                      Patterns::Integer(1),
                      "m of thesis ch. 2.5.");
    prm.declare_entry("Gradient tolerance",
                      "1e-6",
                      Patterns::Double(0),
                      "Stop when the (scaled) gradient norm fell below this "
                      "fraction of the first one.");
    prm.declare_entry("Normalize objective",
                      "false",
                      Patterns::Bool(),
                      "Let L-BFGS see J / |J(q0)|: its first steps then do "
                      "not depend on the units of J (use it when J is far "
                      "from 1, e.g. a small target misfit, which otherwise "
                      "creeps for many iterations before the secant model "
                      "takes over).");
    prm.declare_entry("Memory",
                      "10",
                      Patterns::Integer(1),
                      "L-BFGS memory (pairs).");
    prm.declare_entry("Remesh quality",
                      "0",
                      Patterns::Double(0, 1),
                      "Remesh the design shape with Gmsh when the smallest "
                      "scaled Jacobian of an accepted design falls below "
                      "this (0: never). Needs shape designs whose other "
                      "blocks do not live on the mesh; 3D needs simplices.");
    prm.declare_entry("Max remeshes",
                      "10",
                      Patterns::Integer(0),
                      "Remeshes for mesh quality at most in one run (the "
                      "remesh of Element removal is not one of them).");
    prm.declare_entry(
      "Outer iterations",
      "0",
      Patterns::Integer(0),
      "max_oi of thesis Algorithm 1: when an L-BFGS run stagnates (see "
      "Relative decrease) or reaches Inner iterations, remesh (Design/Remesh "
      "boundary says how) and start a fresh L-BFGS run on the new mesh, up "
      "to this many runs (remeshes for Remesh quality start one too); stop "
      "when a whole run lowered J by less than Relative decrease times |J0|. "
      "Objective terms with 'final weight' ramp their weights over these "
      "runs. Max iterations still bounds the total. 0: one run, remeshed "
      "only for Remesh quality.");
    prm.declare_entry(
      "Outer step",
      "remesh",
      Patterns::Selection("remesh|refine"),
      "What ends an outer iteration (Outer iterations) of the elasticity "
      "apps: remesh (Gmsh, Design/Remesh boundary), or refine: refine the "
      "mesh in place where Finite element/Error indicator of the current "
      "design is largest (Refine fraction of the cells; Kelly or the goal "
      "estimate of Objective/Terms), so that the next run optimizes a more "
      "accurate objective. The design is carried over: shape offsets are "
      "interpolated at the new vertices (the same shape), cell material "
      "entries go to the children. refine needs Finite element/Adaptivity "
      "= h, a quad/hex mesh and a static problem, and excludes Remesh "
      "quality and Element removal.");
    prm.declare_entry("Inner iterations",
                      "0",
                      Patterns::Integer(0),
                      "oi_max_ii of thesis Algorithm 1: accepted iterations "
                      "of one run between remeshes at most (with Outer "
                      "iterations); 0: no limit. After a remesh that "
                      "failed or a refinement that was refused, the run "
                      "goes on on its mesh without this limit.");
    prm.declare_entry(
      "Hold blocked vertices",
      "false",
      Patterns::Bool(),
      "When a run would stop (relative decrease, a vanished step or ROL's "
      "own stop) while the mesh-quality guard (Design/Min scaled Jacobian) "
      "rejected line search trials in its last decrease window, hold the "
      "vertices of the cells that blocked each line search's last rejected "
      "trial (their gradient entries are zeroed) and go on with the rest "
      "of the shape, at most 10 times per mesh; a remesh releases them "
      "(Resume starts with none held). With boundary shape parameters only "
      "the blocking cells' boundary vertices can be held. Without it the "
      "run stops there, as thesis ch. 2.5 does ('step size going to zero "
      "for geometric reasons').");
    prm.declare_entry("Element removal",
                      "0",
                      Patterns::Double(0, 1),
                      "ESO-like topology step (thesis ch. 2.7.1, tower "
                      "crane): once the shape optimization has stopped, "
                      "remove the cells whose stress (cell mean, averaged "
                      "with the face neighbours) is below this fraction of "
                      "the largest, remesh with the holes and optimize on; "
                      "a volume bound then holds the volume left. Cells on "
                      "supports, loads, contacts and interfaces stay. 0: "
                      "never.");
    prm.declare_entry("Element removal boundary",
                      "-1",
                      Patterns::Integer(-1, 255),
                      "Boundary id of the holes that Element removal "
                      "makes: a free (designable) id; cells on it may go, "
                      "cells on any other boundary id stay.");
    prm.declare_entry(
      "Volume minimization iterations",
      "0",
      Patterns::Integer(0),
      "Thesis Table 2.2's 'Post vol. min.': once the optimization above has "
      "stopped, this many more iterations minimize the volume with the "
      "stress held. The second stage's objective is k (J0 (V / V1 + w P) + "
      "the other terms of Objective/Terms (assembly, disassembly, alignment, "
      "smoothing, as they were)), V the volume of the material of the one "
      "stress (or von mises) term, P the stress bound's penalty (see Volume "
      "minimization stress bound), V1 the volume when the stage starts, J0 "
      "the first objective, k such that the stage's first step is as long "
      "as the first stage's (not with Normalize objective, which divides k "
      "out). The stage is an outer iteration of its own; Relative decrease "
      "compares with the first J0. One load case. 0: no second stage.");
    prm.declare_entry(
      "Volume minimization stress bound",
      "peak",
      Patterns::Selection("peak|norm"),
      "What the volume minimization holds. peak: the stress at every point, "
      "P = int max(s - (1 + slack) s1, 0)^2 / (s1^2 V1) with s the stress "
      "term's measure (Frobenius or von Mises) and s1 its largest value "
      "when the stage starts (Frobenius: in the term's material; von Mises: "
      "in all parts). norm: the stress "
      "term's L^p norm S, P = max(S / S1 - 1 - slack, 0)^2 (a peak may "
      "then rise where it narrows).");
    prm.declare_entry("Volume minimization stress slack",
                      "0.02",
                      Patterns::Double(0),
                      "How far the stress (peak or norm) may rise above its "
                      "value at the end of the stress optimization while the "
                      "volume is minimized (a fraction).");
    prm.declare_entry("Volume minimization stress weight",
                      "1e5",
                      Patterns::Double(0),
                      "w in the volume minimization's objective: the weight "
                      "of the stress bound's penalty (on the connector, 1e3 "
                      "let the peak rise 9%, 1e5 2.3%, 1e7 2.0%).");
    prm.declare_entry("Resume",
                      "false",
                      Patterns::Bool(),
                      "Continue a killed run from "
                      "<Output directory>/optimization.checkpoint.json as "
                      "the uninterrupted run would have gone on (the "
                      "checkpoint keeps the L-BFGS memory; a later stage, "
                      "e.g. Volume minimization, restarts it).");
    prm.leave_subsection();
  }



  void
  OptimizationParameters::parse(ParameterHandler &prm)
  {
    prm.enter_subsection("Optimization");
    max_iterations     = prm.get_integer("Max iterations");
    relative_decrease  = prm.get_double("Relative decrease");
    decrease_window    = prm.get_integer("Decrease window");
    gradient_tolerance = prm.get_double("Gradient tolerance");
    memory             = prm.get_integer("Memory");
    normalize          = prm.get_bool("Normalize objective");
    resume             = prm.get_bool("Resume");
    remesh_quality     = prm.get_double("Remesh quality");
    max_remeshes       = prm.get_integer("Max remeshes");
    outer_iterations   = prm.get_integer("Outer iterations");
    inner_iterations   = prm.get_integer("Inner iterations");
    outer_step         = prm.get("Outer step");
    AssertThrow(outer_step == "remesh" ||
                  (outer_iterations > 0 && remesh_quality == 0),
                ExcMessage("Optimization/Outer step = refine ends outer "
                           "iterations: it needs Outer iterations > 0, and "
                           "Remesh quality = 0 (a refined mesh is not "
                           "remeshed)."));
    AssertThrow(inner_iterations == 0 || outer_iterations > 0,
                ExcMessage("Optimization/Inner iterations needs Outer "
                           "iterations (thesis Algorithm 1's outer loop)."));
    hold_blocked_vertices    = prm.get_bool("Hold blocked vertices");
    element_removal          = prm.get_double("Element removal");
    element_removal_boundary = prm.get_integer("Element removal boundary");
    volume_minimization = prm.get_integer("Volume minimization iterations");
    volume_minimization_slack =
      prm.get_double("Volume minimization stress slack");
    volume_minimization_weight =
      prm.get_double("Volume minimization stress weight");
    volume_minimization_bound = prm.get("Volume minimization stress bound");
    AssertThrow(element_removal == 0 || element_removal_boundary >= 0,
                ExcMessage("Optimization/Element removal needs 'Element "
                           "removal boundary': the boundary "
                           "id the holes get (a free, designable id)."));
    AssertThrow(element_removal == 0 || outer_iterations == 0,
                ExcMessage("Optimization/Element removal and Outer "
                           "iterations cannot be combined (the removal "
                           "is a stage of its own after the shape has "
                           "converged)."));
    AssertThrow(element_removal < 1,
                ExcMessage("Optimization/Element removal must be below 1 "
                           "(a fraction of the largest cell stress)."));
    AssertThrow(element_removal == 0 || !resume,
                ExcMessage("Optimization/Resume is not available with "
                           "Element removal (the removal would run again)."));
    prm.leave_subsection();
  }



  namespace
  {
    std::string
    fmt(const double x, const int digits = 6)
    {
      std::ostringstream s;
      s << std::setprecision(digits) << x;
      return s.str();
    }

    // State shared by the ROL objective and the status test.
    struct Run
    {
      Run(const DesignModel            &model,
          const OptimizationParameters &parameters,
          RunContext                   &context)
        : model(model)
        , parameters(parameters)
        , context(context)
      {}

      const DesignModel            &model;
      const OptimizationParameters &parameters;
      RunContext                   &context;
      std::vector<double>           z_accepted;
      std::vector<double>           history;
      std::vector<double>           gradient_norms;
      double                        gnorm0 = 0;
      std::string                   stop_reason;
      std::string                   checkpoint;
      /// The decrease window's first iteration (parameters', or a resumed
      /// run's checkpoint's).
      unsigned int window_start = 0;
      /// Optimization/Normalize objective: ROL sees J / J_scale, |J(q0)|.
      double J_scale = 0;
      /// ROL's L-BFGS memory, kept in the checkpoint.
      ROL::Ptr<ROL::Secant<double>> secant;
      /// The last step's norm before the checkpoint a run resumed from (-1:
      /// none), for the first stopping test, which stands for the
      /// interrupted run's.
      double resumed_step_norm = -1;

      std::vector<double>
      design(const std::vector<double> &z) const
      {
        std::vector<double> q(model.initial);
        for (unsigned int i = 0; i < q.size(); ++i)
          q[i] += model.scale[i] * z[i];
        return q;
      }
    };

    class Objective : public ROL::Objective<double>
    {
    public:
      explicit Objective(Run &run)
        : run(run)
      {}

      double
      value(const ROL::Vector<double> &x, double &) override
      {
        const auto &z =
          *dynamic_cast<const ROL::StdVector<double> &>(x).getVector();
        try
          {
            const double J = run.model.value(run.design(z));
            last_z         = z;
            last_J         = J;
            return J / scale_of(J);
          }
        catch (const std::exception &e)
          {
            // A failed trial: an inverted or degenerate design, or a forward
            // solve that did not converge. A huge value makes the line
            // search shorten the step.
            run.context.log("  rejected trial step: " + error_message(e));
            return failed_value();
          }
      }

      void
      gradient(ROL::Vector<double>       &g,
               const ROL::Vector<double> &x,
               double &) override
      {
        const auto &z =
          *dynamic_cast<const ROL::StdVector<double> &>(x).getVector();
        auto &gz = *dynamic_cast<ROL::StdVector<double> &>(g).getVector();
        std::vector<double> dJ;
        last_J             = run.model.gradient(run.design(z), dJ);
        last_z             = z;
        const double scale = scale_of(last_J);
        for (unsigned int i = 0; i < gz.size(); ++i)
          gz[i] = dJ[i] * run.model.scale[i] / scale; // chain rule via q(z)
      }

      void
      update(const ROL::Vector<double> &x, bool flag, int iter) override
      {
        if (!flag || iter < 0)
          return;
        const auto &z =
          *dynamic_cast<const ROL::StdVector<double> &>(x).getVector();
        if (iter > 0 && z == run.z_accepted)
          return;
        if (z != last_z)
          value(x, dummy);
        run.z_accepted       = z;
        const unsigned int k = run.history.size();
        run.history.push_back(last_J);
        run.model.accepted(k, run.design(z), last_J);
        const double      J0 = run.history.front();
        const std::string line =
          "[iteration " + std::to_string(k) + "/" +
          std::to_string(run.parameters.max_iterations) +
          "] J = " + fmt(last_J) +
          (k > 0 ? ", J/J0 = " + fmt(last_J / J0, 4) : std::string());
        if (run.parameters.print_iterations)
          run.context.print(line);
        else
          run.context.log(line);
        if (k < run.parameters.max_iterations && run.model.remesh_needed &&
            run.model.remesh_needed())
          run.stop_reason = remesh_stop;
      }

      double
      failed_value() const
      {
        return 1e30 *
               (1. + std::abs(run.history.empty() ? 0. : run.history.front()));
      }

    private:
      Run                &run;
      std::vector<double> last_z;
      double              last_J = 0, dummy = 0;

      double
      scale_of(const double J)
      {
        if (run.J_scale == 0)
          run.J_scale =
            run.parameters.normalize && std::abs(J) > 0 ? std::abs(J) : 1.;
        return run.J_scale;
      }
    };



    // Resume point: the last accepted design, with what the steps after it
    // depend on (the L-BFGS memory, the objective's scale), so a resumed run
    // goes on as the uninterrupted one would. Written by the status test,
    // after ROL has updated its memory with the accepted step.
    void
    write_checkpoint(const Run &run, const double step_norm)
    {
      if (!run.context.is_root() || !run.parameters.checkpoint ||
          run.history.empty())
        return;
      nlohmann::json c;
      c["iteration"]       = run.history.size() - 1;
      c["design"]          = run.design(run.z_accepted);
      c["z"]               = run.z_accepted;
      c["mesh"]            = run.model.mesh;
      c["history"]         = run.history;
      c["gradient_norms"]  = run.gradient_norms;
      c["objective_scale"] = run.J_scale;
      c["normalized"]      = run.parameters.normalize;
      c["step_norm"]       = std::isfinite(step_norm) ? step_norm : -1.;
      // JSON has no NaN: a broken run's memory is not kept (a resume then
      // restarts it).
      if (std::all_of(run.gradient_norms.begin(),
                      run.gradient_norms.end(),
                      [](const double g) { return std::isfinite(g); }))
        c["lbfgs"] = internal::secant_to_json(*run.secant);
      c["decrease_window_start"] = run.window_start;
      c["outer_iteration"]       = run.parameters.outer_iteration;
      c["outer_start"]           = run.parameters.outer_start;
      if (!run.parameters.outer_possible)
        c["outer_possible"] = false;
      c["job_first_gradient_norm"] = run.parameters.first_gradient_norm > 0 ?
                                       run.parameters.first_gradient_norm :
                                       run.gnorm0;
      if (!run.parameters.stage_terms.empty())
        {
          c["stage_terms"] = run.parameters.stage_terms;
          c["stage_start"] = run.parameters.stage_start;
        }
      // A failed write (a full disk) costs only the resumability: the last
      // checkpoint stays whole. Logged, not thrown (on root alone it would
      // leave the other ranks waiting).
      try
        {
          if (run.model.records)
            c["records"] = nlohmann::json::parse(run.model.records());
          replace_file_text(run.checkpoint, c.dump());
        }
      catch (const std::exception &e)
        {
          run.context.log("checkpoint not written: " + error_message(e));
        }
    }

    // The stopping rule of thesis ch. 2.5 and the iteration limit.
    class StatusTest : public ROL::StatusTest<double>
    {
    public:
      explicit StatusTest(Run &run)
        : ROL::StatusTest<double>(1e-300, 1e-300, 1000000)
        , run(run)
      {}

      bool
      check(ROL::AlgorithmState<double> &state) override
      {
        const auto        &h = run.history;
        const unsigned int k = h.empty() ? 0 : h.size() - 1;
        if (run.gnorm0 == 0)
          run.gnorm0 = state.gnorm;
        run.gradient_norms.push_back(state.gnorm);
        // A resumed run's first test stands for the interrupted run's.
        const bool resumed =
          state.iter == 0 && run.resumed_step_norm >= 0 && k > 0;
        const double step_norm =
          resumed ? run.resumed_step_norm : (state.iter > 0 ? state.snorm : -1);
        write_checkpoint(run, step_norm);
        if (!run.stop_reason.empty())
          ; // decided in Objective::update (a remesh)
        else if (!h.empty() && h.back() <= run.parameters.value_target)
          run.stop_reason = "target value reached";
        else if (k >= run.parameters.max_iterations)
          run.stop_reason = "maximum number of iterations";
        else if (state.gnorm <= run.parameters.gradient_tolerance * run.gnorm0)
          run.stop_reason = "gradient tolerance";
        else if (step_norm >= 0 && step_norm <= 1e-12)
          run.stop_reason = step_vanished;
        else if (h.size() > run.window_start + run.parameters.decrease_window &&
                 h[h.size() - 1 - run.parameters.decrease_window] - h.back() <
                   run.parameters.relative_decrease * std::abs(h.front()))
          run.stop_reason = relative_decrease_stop +
                            fmt(run.parameters.relative_decrease) + " over " +
                            std::to_string(run.parameters.decrease_window) +
                            " iterations";
        return run.stop_reason.empty();
      }

    private:
      Run &run;
    };
  } // namespace



  std::string
  checkpoint_directory(const RunContext &context)
  {
    return std::filesystem::path(context.directory()).parent_path().string();
  }



  namespace
  {
    std::string
    checkpoint_file(const RunContext &context)
    {
      return (std::filesystem::path(checkpoint_directory(context)) /
              "optimization.checkpoint.json")
        .string();
    }

    nlohmann::json
    read_checkpoint(const RunContext &context)
    {
      const std::string file = checkpoint_file(context);
      std::ifstream     in(file);
      AssertThrow(in,
                  ExcMessage("Optimization/Resume: there is no checkpoint '" +
                             file + "' to resume from."));
      nlohmann::json c;
      try
        {
          in >> c;
          c.at("design").get<std::vector<double>>();
          AssertThrow(!c.at("history").get<std::vector<double>>().empty(),
                      ExcMessage("its history is empty"));
          c.at("mesh").get<std::string>();
        }
      catch (const std::exception &e)
        {
          AssertThrow(false,
                      ExcMessage("Optimization/Resume: the checkpoint '" +
                                 file + "' is unreadable: " + e.what()));
        }
      return c;
    }



    // Projected L-BFGS with a backtracking line search; forma's status test
    // decides when to stop.
    ROL::ParameterList
    rol_parameters(const OptimizationParameters &parameters)
    {
      ROL::ParameterList list;
      list.sublist("General").set("Output Level", 1);
      list.sublist("General").sublist("Secant").set("Type",
                                                    "Limited-Memory BFGS");
      list.sublist("General").sublist("Secant").set(
        "Maximum Storage", static_cast<int>(parameters.memory));
      list.sublist("Step").set("Type", "Line Search");
      list.sublist("Step")
        .sublist("Line Search")
        .sublist("Descent Method")
        .set("Type", "Quasi-Newton Method");
      list.sublist("Step")
        .sublist("Line Search")
        .sublist("Line-Search Method")
        .set("Type", "Backtracking");
      list.sublist("Step")
        .sublist("Line Search")
        .set("Function Evaluation Limit", 30);
      // The forma status test decides; ROL's own tests are switched off.
      list.sublist("Status Test").set("Gradient Tolerance", 1e-300);
      list.sublist("Status Test").set("Step Tolerance", 1e-300);
      list.sublist("Status Test").set("Iteration Limit", 1000000);
      return list;
    }



    // What makes the resumed steps the uninterrupted run's: the scaled
    // variables themselves, the objective's scale, the gradient norms and
    // the L-BFGS memory. Only if the checkpoint was written from this run's
    // start design, scales and normalization; a later stage starts from
    // another design, and there the memory restarts (false).
    bool
    restore_memory(Run &run, const nlohmann::json &c, std::vector<double> &z)
    {
      if (!c.contains("lbfgs") || !c.contains("normalized") ||
          c.at("normalized") != run.parameters.normalize)
        return false;
      const auto zc = c.at("z").get<std::vector<double>>();
      const auto q  = c.at("design").get<std::vector<double>>();
      AssertThrow(zc.size() == z.size(), ExcMessage("z has another size"));
      const auto from_z = run.design(zc);
      for (unsigned int i = 0; i < q.size(); ++i)
        if (!(std::abs(from_z[i] - q[i]) <= 1e-12 * (1 + std::abs(q[i]))))
          return false;
      const double scale = c.at("objective_scale").get<double>();
      auto         norms = c.at("gradient_norms").get<std::vector<double>>();
      AssertThrow(std::isfinite(scale) && scale > 0 && !norms.empty() &&
                    std::all_of(norms.begin(),
                                norms.end(),
                                [](const double g) {
                                  return std::isfinite(g);
                                }),
                  ExcMessage("a bad objective scale or gradient norm"));
      internal::secant_from_json(c.at("lbfgs"), z.size(), *run.secant);
      z                  = zc;
      run.J_scale        = scale;
      run.gnorm0         = norms.front();
      run.gradient_norms = std::move(norms);
      run.gradient_norms.pop_back(); // this run's first, again
      const double step_norm = c.value("step_norm", -1.);
      run.resumed_step_norm  = std::isfinite(step_norm) ? step_norm : -1.;
      return true;
    }



    // Continue from the checkpoint: the design and the history before it
    // (that iterate is recorded again as this run's first), and where it
    // can, the L-BFGS memory with it (restore_memory()).
    void
    resume(Run &run, std::vector<double> &z)
    {
      const auto         c = read_checkpoint(run.context);
      const unsigned int n = z.size();
      const auto         q = c.at("design").get<std::vector<double>>();
      AssertThrow(q.size() == n && c.at("mesh") == run.model.mesh,
                  ExcMessage("Optimization/Resume: the checkpoint holds a "
                             "design of another design space."));
      for (unsigned int i = 0; i < n; ++i)
        z[i] = (q[i] - run.model.initial[i]) / run.model.scale[i];
      bool exact = false;
      try
        {
          exact = restore_memory(run, c, z);
        }
      catch (const std::exception &e)
        {
          AssertThrow(false,
                      ExcMessage("Optimization/Resume: the checkpoint '" +
                                 run.checkpoint +
                                 "' is unreadable: " + error_message(e)));
        }
      if (!exact)
        run.context.log("resumed with the L-BFGS memory restarted (the "
                        "checkpoint has none, or another start design)");
      run.history = c.at("history").get<std::vector<double>>();
      run.history.pop_back();
      // A window restarted by a remesh before the stop stays restarted.
      run.window_start =
        std::max(run.window_start, c.value("decrease_window_start", 0u));
      run.context.print("resuming from iteration " +
                        std::to_string(run.history.size()));
    }
  } // namespace



  CheckpointPlace
  checkpoint_place(const RunContext &context)
  {
    const auto      c = read_checkpoint(context);
    CheckpointPlace place;
    try
      {
        place = {c.at("mesh").get<std::string>(),
                 c.value("outer_iteration", 1u),
                 c.value("outer_start", 0u),
                 c.value("stage_terms", std::string()),
                 c.value("stage_start", 0u),
                 c.value("outer_possible", true),
                 c.value("job_first_gradient_norm", 0.),
                 static_cast<unsigned int>(c.at("history").size() - 1),
                 c.contains("records") ? c.at("records").dump() : ""};
      }
    catch (const std::exception &e)
      {
        AssertThrow(false,
                    ExcMessage("Optimization/Resume: the checkpoint '" +
                               checkpoint_file(context) +
                               "' is unreadable: " + error_message(e)));
      }
    return place;
  }



  OptimizationResult
  optimize(const DesignModel            &model,
           const OptimizationParameters &parameters,
           RunContext                   &context,
           const std::vector<double>    &previous_history)
  {
    const unsigned int n = model.initial.size();
    AssertThrow(model.scale.size() == n && model.lower.size() == n &&
                  model.upper.size() == n,
                ExcInternalError());
    Run run(model, parameters, context);
    run.checkpoint   = checkpoint_file(context);
    run.window_start = parameters.decrease_window_start;
    // The previous run's last design is this run's first: its value on
    // the new mesh replaces the old one.
    run.history = previous_history;
    if (!run.history.empty())
      run.history.pop_back();

    ROL::ParameterList list = rol_parameters(parameters);
    run.secant              = ROL::SecantFactory<double>(list);
    auto z                  = ROL::makePtr<std::vector<double>>(n, 0.);
    if (parameters.resume)
      resume(run, *z);

    // Bounds in z.
    auto lo = ROL::makePtr<std::vector<double>>(n),
         hi = ROL::makePtr<std::vector<double>>(n);
    for (unsigned int i = 0; i < n; ++i)
      {
        const double s = model.scale[i];
        (*lo)[i]       = std::isfinite(model.lower[i]) ?
                           (model.lower[i] - model.initial[i]) / s :
                           ROL::ROL_NINF<double>();
        (*hi)[i]       = std::isfinite(model.upper[i]) ?
                           (model.upper[i] - model.initial[i]) / s :
                           ROL::ROL_INF<double>();
      }

    auto objective = ROL::makePtr<Objective>(run);
    auto x         = ROL::makePtr<ROL::StdVector<double>>(z);
    auto bounds    = ROL::makePtr<ROL::Bounds<double>>(
      ROL::makePtr<ROL::StdVector<double>>(lo),
      ROL::makePtr<ROL::StdVector<double>>(hi));
    // ROL's projected L-BFGS line search, as OptimizationSolver would set
    // it up for a bound-constrained problem, but with the secant memory in
    // hand (the checkpoint keeps it). (ROL leaves the step's secant name
    // unset when it is given a secant: log.txt may name it wrongly.) ROL's own
    // status test comes first.
    auto step =
      ROL::makePtr<ROL::LineSearchStep<double>>(list, ROL::nullPtr, run.secant);
    // forma's status test first: ROL's combined test stops at the first
    // that says stop, and forma's writes the checkpoint.
    auto status = ROL::makePtr<ROL::CombinedStatusTest<double>>();
    status->add(ROL::makePtr<StatusTest>(run));
    status->add(ROL::makePtr<ROL::StatusTest<double>>(list));
    ROL::Algorithm<double> algorithm(step, status);
    std::ostringstream     rol_output;
    algorithm.run(
      *x, *x->dual().clone(), *objective, *bounds, true, rol_output);
    context.log(rol_output.str());

    OptimizationResult result;
    result.design         = run.design(run.z_accepted);
    result.history        = run.history;
    result.gradient_norms = run.gradient_norms;
    result.stop_reason =
      run.stop_reason.empty() ? rol_stopped : run.stop_reason;
    return result;
  }
} // namespace forma
