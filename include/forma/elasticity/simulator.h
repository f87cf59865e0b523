#ifndef forma_elasticity_simulator_h
#define forma_elasticity_simulator_h

#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/lac/vector.h>

#include <forma/adjoint/design.h>
#include <forma/adjoint/objective.h>
#include <forma/elasticity/parameters.h>

#include <nlohmann/json.hpp>

#include <functional>
#include <limits>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
}

namespace forma
{
  class RunContext;

  /**
   * Forward elasticity without contact (thesis ch. 3.6-3.7.2): linear or
   * Neo-Hookean bodies, Dirichlet/traction/pressure/gravity/body-force loads,
   * static Newton solves with load stepping, BDF1-6 transient solves with
   * strain-rate damping, h/hp adaptivity, distributed over MPI ranks (p4est
   * and Trilinos) with threaded assembly.
   *
   * The residual of a step is
   *   R(u) = M (u + w) / (beta dt)^2 + f_int(u) + f_damp(u, u^{i-1}) - f_ext(t)
   * with w the BDF history (thesis eq. 3.12 solved for u^i); static problems
   * drop the inertia and damping terms.
   *
   * Heavy deal.II/Trilinos types stay behind a pointer to keep this header
   * cheap for applications and tests.
   */
  template <int dim>
  class ElasticitySimulator
  {
  public:
    struct StepRecord
    {
      unsigned int                        step;
      double                              time;
      unsigned int                        newton_iterations;
      unsigned int                        linear_iterations;
      double                              residual;
      unsigned long long                  n_dofs; ///< of the step's mesh
      double                              kinetic_energy;
      double                              elastic_energy;
      double                              gravity_potential; ///< -int rho g . u
      dealii::Tensor<1, dim>              mean_displacement; ///< mass-weighted
      std::vector<dealii::Tensor<1, dim>> point_displacements;
      /// IPC: active pairs, smallest distance, barrier stiffness, steps
      /// cut by CCD, inverted elements (null without IPC).
      nlohmann::json contact;
    };

    struct CycleRecord
    {
      unsigned int       cycle;
      unsigned int       n_cells;
      unsigned long long n_dofs;
      /// Error indicator = goal: J(u_h) and the estimate of J(u) - J(u_h)
      /// (signed sum of the indicators); NaN otherwise.
      double objective = std::numeric_limits<double>::quiet_NaN();
      double estimate  = std::numeric_limits<double>::quiet_NaN();
    };

    ElasticitySimulator(const ElasticityParameters &parameters,
                        const MPI_Comm              comm);
    ~ElasticitySimulator();

    /// Run the whole job; writes VTU/PVD and fills the summary of `context`
    /// when one is given (tests may pass none).
    void
    run(RunContext *context = nullptr);

    /// Called after each solved adaptive cycle (static) with its index.
    void
    set_cycle_callback(const std::function<void(unsigned int)> &callback);

    dealii::Tensor<1, dim>
    point_displacement(const dealii::Point<dim> &p) const;

    /**
     * Every active cell with the displacement of the last solved state at
     * its vertices, by global active cell index, on every rank: (vertex of
     * the mesh, without shape-design offsets; displacement) pairs, around
     * the cell in 2D. For pictures of deformed meshes.
     */
    std::vector<
      std::vector<std::pair<dealii::Point<dim>, dealii::Tensor<1, dim>>>>
    cell_vertex_displacements() const;

    /// Force exerted by the supports on the body through boundary `id`.
    dealii::Tensor<1, dim>
    reaction(const unsigned int boundary_id) const;

    /// L2 norm (or H1 seminorm) of u_h - exact over the domain.
    double
    error_norm(const dealii::Function<dim> &exact,
               const bool                   h1_seminorm) const;

    unsigned long long
    n_dofs() const;

    const std::vector<StepRecord> &
    steps() const;

    const std::vector<CycleRecord> &
    cycles() const;

    /// The run's key results as JSON (what summary.json holds).
    nlohmann::json
    summary() const;

    /**
     * @name Adjoint layer (thesis ch. 3.3-3.8)
     *
     * The design vector holds the blocks chosen in the `Design` section
     * (see DesignParameters). Typical use: prepare(), set_objective(),
     * then per design set_design(), solve_design(), objective() and
     * gradient().
     */
    //@{
    /// Set up the mesh (running the adaptive cycles first, if any) and the
    /// design space at the starting design.
    void
    prepare(RunContext *context = nullptr);

    const DesignLayout &
    design_layout() const;

    /// The current design (after prepare(): the starting design).
    const std::vector<double> &
    design() const;

    /// Move to design q; throws with a message if q is inadmissible
    /// (inverted cells, materials out of range).
    void
    set_design(const std::vector<double> &q);

    /// Per design entry, the size of a meaningful move around q0 (each
    /// block's parameterization decides: the cell size for shapes, the
    /// magnitude for materials); optimizers and Taylor tests scale by it.
    std::vector<double>
    design_scales(const std::vector<double> &q0) const;

    /// The admissible box around q0 (each block's parameterization
    /// decides; shape entries within `shape_bound` of their material
    /// position, infinite: free).
    void
    design_bounds(const std::vector<double> &q0,
                  const double               shape_bound,
                  std::vector<double>       &lower,
                  std::vector<double>       &upper) const;

    /// Use J; runs the reference simulation first if a term needs one.
    void
    set_objective(const std::shared_ptr<const Objective<dim>> &J);

    /// Forward solve for the current design, without output; stores the
    /// states the adjoint needs. Throws with a message if it fails.
    void
    solve_design();

    /// Time/Integrator = adaptive: later solve_design() calls reuse the
    /// time levels of the last transient run (or choose them once and then
    /// keep them), so that J is one smooth function of the design for a
    /// Taylor test. No effect on fixed steps.
    void
    freeze_time_steps(const bool freeze);

    /// Time/Integrator = adaptive (and a transient problem).
    bool
    adaptive_time_steps() const;

    /// J at the last solved design.
    double
    objective() const;

    /// The weighted terms of the last objective() value, by name.
    std::vector<std::pair<std::string, double>>
    objective_terms() const;

    /// J and dJ/dq at the last solved design, by the adjoint method.
    double
    gradient(std::vector<double> &dJ) const;

    /// Write the last solved state (final step) as VTU number `index` of
    /// the output series, on the current design's shape.
    void
    write_state(const unsigned int index, RunContext &context);

    /**
     * Of the last solved state (final step): the largest von Mises and
     * Frobenius (in-plane for 2D, the measure of the stress objective)
     * Cauchy stress at the quadrature points (and per material id when
     * there are several), the volume (area) of the current design, and the
     * contact statistics (when there is contact).
     */
    nlohmann::json
    state_statistics() const;

    /// Largest coordinate change of a vertex of the current design from
    /// the mesh as read.
    double
    max_shape_offset() const;

    /// Smallest cell diameter of the mesh (a length scale for designs).
    double
    cell_size() const;

    /// Centers of the active cells of the current design by global active
    /// cell index (the order of the `cell material` block), on every rank.
    std::vector<dealii::Point<dim>>
    cell_centers() const;

    /**
     * @name Remeshing
     *
     * Shape optimization can flatten cells; remesh() replaces the mesh by a
     * Gmsh mesh of the current design's shape (keeping every boundary and
     * interface vertex, the boundary ids and the material ids). The new
     * mesh is the origin of later shape designs; loads, boundary values,
     * targets and shape bounds keep referring to the material coordinates
     * of the mesh as read, which are carried over to the new vertices by
     * interpolation. Non-shape design blocks keep their values; blocks
     * that live on the mesh (cell material, fields) cannot be remeshed.
     */
    //@{
    /// Smallest scaled Jacobian det J / prod |J e_k| over the quadrature
    /// points of the current design, and its cells' corners unless
    /// Design/Check corners = false (1: undistorted, <= 0: inverted).
    double
    mesh_quality() const;

    /// Check the shape's quality (Design/Min scaled Jacobian) at the cells'
    /// corners as well as at the quadrature points: a bilinear cell can
    /// fold at a corner unseen by its quadrature points, and the cells of a
    /// refinement would meet the fold.
    void
    guard_cell_corners(const bool on);

    /// Design entries of the shape DoFs (and the DoFs they are constrained
    /// to) of every cell whose scaled Jacobian in the current shape is
    /// below `threshold`, sorted, on every rank: where the quality guard
    /// blocks a design.
    std::vector<unsigned int>
    degenerate_shape_entries(const double threshold) const;

    /// Whether remesh() would succeed and improve the quality now; if not,
    /// says why. The mesh it makes is kept for remesh().
    bool
    remesh_improves(std::string &reason);

    /// Remesh the current design (if Gmsh fails or the new mesh violates
    /// Design/Min scaled Jacobian, throws and leaves the simulator as it
    /// was); writes `<file_stem>.msh` and
    /// `<file_stem>.json` (material coordinates) for load_remeshed() unless
    /// `file_stem` is empty. Returns a one-line description.
    std::string
    remesh(const std::string &file_stem);

    /// Continue on a mesh written by remesh().
    void
    load_remeshed(const std::string &file_stem);

    /// Back to the mesh and design before the last remesh(),
    /// remesh_without() or load_remeshed() not yet committed (say, when
    /// the design cannot be solved on the new mesh); false if there is
    /// none.
    bool
    undo_remesh();

    /// Keep the current mesh: forget the one before it.
    void
    commit_remesh();

    /// Mean Frobenius stress of every active cell in the last state, by
    /// active cell index, on every rank (needs every cell on every rank).
    std::vector<double>
    cell_mean_stress() const;

    /// Boundary ids that hold the bodies: Dirichlet conditions and
    /// contacts.
    std::set<dealii::types::boundary_id>
    holding_boundaries() const;

    /// Lower every one-sided volume bound of the objective to the volume
    /// it measures now (its own material restriction included).
    void
    cap_volume_bounds();

    /// The current mesh (as read or last remeshed; the design moves its
    /// vertices through the mapping, not here).
    const dealii::Triangulation<dim, dim> &
    triangulation() const;

    /// remesh() without the cells flagged in `removed` (by active cell
    /// index, e.g. from select_low_stress_cells()); the faces they leave
    /// open get boundary id `open_id`.
    std::string
    remesh_without(const std::string         &file_stem,
                   const std::vector<bool>   &removed,
                   dealii::types::boundary_id open_id);

    /// Per design entry: for shape entries, the shape design that puts the
    /// vertex back at its material position (zero before any remesh), the
    /// center of bounds around the mesh as read; zero elsewhere.
    std::vector<double>
    material_offsets() const;

    unsigned int
    n_remeshes() const;
    //@}

    /**
     * @name Refinement of a design
     *
     * Quad/hex meshes refine in place (p4est, hanging nodes) between
     * optimization iterations, for the objective's accuracy. The design is
     * carried over: shape offsets are interpolated at the new vertices,
     * which keeps the shape exactly (the shape field is bi/trilinear); a
     * refined cell's children take its entries of blocks per cell (cell
     * material); per-body and global blocks keep their values. Static
     * problems; not with IPC.
     */
    //@{
    /// Error indicators of the current design's state, per active cell of
    /// this rank (Finite element/Error indicator: Kelly's, with the contact
    /// residual where Contact residual says so, or the goal estimate of
    /// Objective/Terms).
    dealii::Vector<float>
    refinement_indicators();

    /// The Refine fraction (Finite element) of the active cells with the
    /// largest `indicators`, as CellId strings, sorted, on every rank.
    std::vector<std::string>
    cells_to_refine(const dealii::Vector<float> &indicators);

    /// Refine `cells` (from cells_to_refine()) and carry the design over;
    /// writes `<file_stem>.refinement.json` (every refinement since the
    /// mesh as read or last remeshed) for load_refinement() unless
    /// `file_stem` is empty. Returns a one-line description.
    std::string
    refine_design(const std::vector<std::string> &cells,
                  const std::string              &file_stem);

    /// Repeat the refinements written by refine_design() on the mesh they
    /// started from (what a resumed run does).
    void
    load_refinement(const std::string &file_stem);

    /// Refinements since the mesh as read or last remeshed.
    unsigned int
    n_refinements() const;
    //@}

    /// Accumulated forward and adjoint wall times, stored-state memory.
    nlohmann::json
    adjoint_statistics() const;
    //@}

  private:
    class Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace forma

#endif
