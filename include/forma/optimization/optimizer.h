#ifndef forma_optimization_optimizer_h
#define forma_optimization_optimizer_h

#include <deal.II/base/parameter_handler.h>

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace forma
{
  class RunContext;

  /// The `Optimization` section.
  struct OptimizationParameters
  {
    unsigned int max_iterations     = 50;
    double       relative_decrease  = 1e-3;  ///< epsilon_r of thesis ch. 2.5
    unsigned int decrease_window    = 2;     ///< m of thesis ch. 2.5
    double       gradient_tolerance = 1e-6;  ///< relative to the first one
    unsigned int memory             = 10;    ///< L-BFGS pairs
    bool         normalize          = false; ///< ROL sees J / |J(q0)|
    bool         resume             = false;
    double       remesh_quality     = 0; ///< remesh below this; 0: never
    unsigned int max_remeshes       = 10;
    /// max_oi of thesis Algorithm 1: a stagnated inner run (or one at
    /// `inner_iterations`) is followed by a remesh and a fresh L-BFGS run,
    /// up to this many runs; 0: remesh on mesh quality only.
    unsigned int outer_iterations = 0;
    /// What ends an outer iteration: "remesh" (Gmsh) or "refine" (the
    /// mesh refined in place for the objective's accuracy).
    std::string outer_step = "remesh";
    /// oi_max_ii of Algorithm 1: iterations of one inner run; 0: no limit.
    unsigned int inner_iterations = 0;
    /// The outer iteration (from 1) this run belongs to and the iteration
    /// it started at, recorded in the checkpoint (not parameter-file
    /// entries).
    unsigned int outer_iteration = 1, outer_start = 0;
    /// False once a remesh failed or a refinement was refused: the run goes
    /// on on its mesh without outer iterations (also in the checkpoint).
    bool outer_possible = true;
    /// The first gradient norm of the whole job (its first run's), so that
    /// a resumed job reports the same relative gradient norm; 0: this run
    /// is the first (recorded in the checkpoint).
    double first_gradient_norm = 0;
    /// Shape optimization: hold the vertices where the mesh-quality guard
    /// blocks the line search and go on (see the parameter's text).
    bool hold_blocked_vertices = false;
    /// ESO-like removal of cells below this fraction of the largest
    /// (filtered) cell stress once the shape has converged, then on with
    /// the holes (thesis ch. 2.7.1); 0: never.
    double element_removal = 0;
    /// Boundary id of the holes (-1: not set).
    int element_removal_boundary = -1;
    /// Thesis Table 2.2's "Post vol. min.": iterations of a second stage
    /// that minimizes the volume with the stress (its peak or its norm,
    /// `volume_minimization_bound`) held within
    /// `volume_minimization_slack` by a penalty of weight
    /// `volume_minimization_weight` (see the parameter's text); 0: none.
    unsigned int volume_minimization        = 0;
    double       volume_minimization_slack  = 0.02;
    double       volume_minimization_weight = 1e5;
    /// What the stage holds: "peak" (the largest stress, pointwise) or
    /// "norm" (the stress term's L^p norm).
    std::string volume_minimization_bound = "peak";
    /// A later stage's Objective/Terms and the iteration it started at,
    /// recorded in the checkpoint (not parameter-file entries; empty: the
    /// first stage).
    std::string  stage_terms;
    unsigned int stage_start = 0;
    /// Stop once J <= this (inverse problems with a reachable target; not
    /// a parameter-file entry).
    double value_target = -std::numeric_limits<double>::infinity();
    /// The decrease window (thesis ch. 2.5) looks at iterations from this
    /// one on: a run continued on a changed problem (element removal, a
    /// remesh) must not compare with values before the change (not a
    /// parameter-file entry).
    unsigned int decrease_window_start = 0;
    /// Iteration lines to the screen (true) or to the log only.
    bool print_iterations = true;
    /// Write the resume checkpoint (false for many small runs, e.g. one
    /// per rank at a time; not a parameter-file entry).
    bool checkpoint = true;

    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(dealii::ParameterHandler &prm);
  };

  /**
   * What the optimizer drives. `value` and `gradient` throw (any exception)
   * when the design is inadmissible or its forward solve fails; the
   * optimizer then treats the trial as a failed step and shortens it.
   * `scale` maps optimization variables z to designs, q = q0 + scale * z,
   * so that every entry moves on a comparable scale (cell sizes for
   * vertices, the values themselves for material constants).
   */
  struct DesignModel
  {
    std::vector<double> initial, scale, lower, upper;
    std::function<double(const std::vector<double> &)> value;
    std::function<double(const std::vector<double> &, std::vector<double> &)>
      gradient;
    /// Called for the starting design (iteration 0) and every accepted one.
    std::function<void(unsigned int, const std::vector<double> &, double)>
      accepted;
    /// Asked after every accepted design (optional): true ends the run
    /// with stop_reason == remesh_stop, so that the caller can remesh and
    /// continue with a new model.
    std::function<bool()> remesh_needed;
    /// The mesh the designs live on, recorded in the checkpoint (a file
    /// stem inside checkpoint_directory(); empty: the parameter file's).
    std::string mesh;
    /// The caller's own records up to the accepted design, as JSON text
    /// (optional): kept in the checkpoint, so that a resumed job reports
    /// what the uninterrupted one would (CheckpointPlace::records).
    std::function<std::string()> records;
  };

  /// The stop reason of a run ended by DesignModel::remesh_needed.
  inline const std::string remesh_stop = "remesh";

  struct OptimizationResult
  {
    std::vector<double> design;
    std::vector<double> history; ///< J of the accepted iterates, first J0
    /// The gradient norm (in the optimizer's scaled variables) at each
    /// status check, the first at the start.
    std::vector<double> gradient_norms;
    std::string         stop_reason;
  };

  /// Whether a run stopped because it stagnated (the decrease rule of
  /// thesis ch. 2.5, a vanished step, ROL's own stop), not on a limit, a
  /// target, the gradient tolerance or a remesh.
  bool
  stagnated(const OptimizationResult &result);

  /**
   * Minimize with ROL: a line-search L-BFGS method, projected onto the
   * bounds (lower/upper, +-inf where free). Stops when the objective fell
   * by less than `relative_decrease` * |J0| over `decrease_window`
   * iterations (thesis ch. 2.5), the gradient fell below
   * `gradient_tolerance` relative to the first one, the step vanished, or
   * after `max_iterations`. After every accepted iterate the design is
   * written to `<output directory>/optimization.checkpoint.json`; with
   * `resume` the run continues from that file as the uninterrupted run
   * would have (the checkpoint keeps the L-BFGS memory).
   *
   * A run continued after a remesh passes the history so far as
   * `previous_history`: its last entry (the design before the remesh) is
   * replaced by the first value of this run, and iterations count on.
   */
  OptimizationResult
  optimize(const DesignModel            &model,
           const OptimizationParameters &parameters,
           RunContext                   &context,
           const std::vector<double>    &previous_history = {});

  /// Where optimize() keeps its checkpoint (and remeshed designs): the
  /// output directory itself, which a failed run leaves untouched.
  std::string
  checkpoint_directory(const RunContext &context);

  /// Where the checkpoint's design lives: its DesignModel::mesh (empty:
  /// the parameter file's) and its outer iteration.
  struct CheckpointPlace
  {
    std::string  mesh;
    unsigned int outer_iteration = 1, outer_start = 0;
    /// See OptimizationParameters::stage_terms (empty: the first stage).
    std::string  stage_terms;
    unsigned int stage_start    = 0;
    bool         outer_possible = true;
    /// See OptimizationParameters::first_gradient_norm (0: not recorded).
    double first_gradient_norm = 0;
    /// The checkpoint's iteration and DesignModel::records there (empty:
    /// none recorded).
    unsigned int iteration = 0;
    std::string  records;
  };

  CheckpointPlace
  checkpoint_place(const RunContext &context);
} // namespace forma

#endif
