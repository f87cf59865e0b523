// The optimize job (Mode = optimize of the elasticity apps), private to
// the library: its set-up, the optimizer's callbacks and thesis Algorithm
// 1's loop (optimize_job.cc), the steps between L-BFGS runs
// (optimize_job_outer.cc) and its results (optimize_job_report.cc).

#ifndef forma_elasticity_optimize_job_impl_h
#define forma_elasticity_optimize_job_impl_h

#include <deal.II/base/timer.h>

#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/elasticity/jobs.h>
#include <forma/elasticity/load_cases.h>
#include <forma/optimization/optimizer.h>

#include <limits>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace forma
{
  namespace internal
  {
    inline std::string
    at_iteration(const std::size_t k)
    {
      return "[iteration " + std::to_string(k) + "] ";
    }

    /// The small (non-shape) design blocks' values, e.g. recovered
    /// materials, and the shape's largest vertex move, as text and in
    /// `json` (optimize_job_report.cc).
    std::string
    describe_design(const DesignLayout        &layout,
                    const std::vector<double> &q0,
                    const std::vector<double> &q,
                    const double               shape_offset,
                    nlohmann::json            &json);



    /// One run of Mode = optimize: L-BFGS runs on a sequence of meshes
    /// (thesis Algorithm 1), their checkpoints and their results.
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
      std::string
      records() const;
      void
      restore_records(const nlohmann::json &records,
                      const unsigned int    iteration);
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

      nlohmann::json history = nlohmann::json::array();
      /// A resumed job's checkpoint iteration, whose history entry (the
      /// interrupted run's) stands; -1: none.
      int         resumed_iteration = -1;
      std::string restart_kind      = "remeshed";
      double      remesh_seconds    = 0;
      bool        remesh_allowed    = false;
      bool        removal_done      = false;
      /// False once a remesh failed or a refinement was refused.
      bool   outer_possible   = true;
      double remeshed_quality = 1;

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
  } // namespace internal
} // namespace forma

#endif
