// Private to the elasticity simulator and its adjoint (not installed).
#ifndef forma_elasticity_simulator_impl_h
#define forma_elasticity_simulator_impl_h

#include <deal.II/base/function_parser.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria_base.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/hp/fe_collection.h>
#include <deal.II/hp/fe_values.h>
#include <deal.II/hp/mapping_collection.h>
#include <deal.II/hp/q_collection.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

#include <forma/adjoint/design.h>
#include <forma/adjoint/form.h>
#include <forma/adjoint/initial_conditions.h>
#include <forma/adjoint/objective.h>
#include <forma/adjoint/parameterization.h>
#include <forma/adjoint/physical_parameters.h>
#include <forma/adjoint/shape_field.h>
#include <forma/base/records.h>
#include <forma/contact/penalty_contact.h>
#include <forma/elasticity/simulator.h>
#include <forma/ipc/ipc_contact.h>
#include <forma/ipc/ipc_contact_form.h>
#include <forma/mesh/boundary_resampling.h>
#include <forma/mesh/harmonic_extension.h>
#include <forma/mesh/remesh.h>
#include <forma/physics/damping.h>
#include <forma/physics/elastic_form.h>
#include <forma/physics/material.h>
#include <forma/physics/time_grid.h>
#include <forma/solvers/linear_solver.h>
#include <forma/solvers/matrix_free_elasticity.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>

namespace forma
{
  using namespace dealii;
  using Vector_t = TrilinosWrappers::MPI::Vector;

  /// The order of points by coordinates (sorted vertex tables).
  template <int dim>
  inline bool
  lexicographically_before(const Point<dim> &a, const Point<dim> &b)
  {
    return std::lexicographical_compare(a.begin_raw(),
                                        a.end_raw(),
                                        b.begin_raw(),
                                        b.end_raw());
  }

  namespace internal
  {
    inline std::string
    fmt(const double v, const int precision = 6)
    {
      std::ostringstream s;
      s << std::setprecision(precision) << v;
      return s.str();
    }

    template <int dim>
    std::string
    fmt(const Tensor<1, dim> &v, const int precision = 6)
    {
      std::string s = "(";
      for (unsigned int d = 0; d < dim; ++d)
        s += (d ? ", " : "") + fmt(v[d], precision);
      return s + ")";
    }

    template <int dim>
    nlohmann::json
    to_json(const Tensor<1, dim> &v)
    {
      nlohmann::json j = nlohmann::json::array();
      for (unsigned int d = 0; d < dim; ++d)
        j.push_back(v[d]);
      return j;
    }

    template <int dim>
    Point<dim>
    parse_point(const std::string &text, const std::string &entry)
    {
      const auto parts = split_top_level(text, ',');
      AssertThrow(parts.size() == dim,
                  ExcMessage("'" + entry + "': the point '" + text +
                             "' needs " + std::to_string(dim) +
                             " coordinates."));
      Point<dim> p;
      for (unsigned int d = 0; d < dim; ++d)
        p[d] = Utilities::string_to_double(parts[d]);
      return p;
    }

    // Per-thread assembly workspace.
    template <int dim>
    struct Scratch
    {
      Scratch(const hp::MappingCollection<dim> &mapping,
              const hp::MappingCollection<dim> &reference_mapping,
              const hp::FECollection<dim>      &fe,
              const hp::QCollection<dim>       &q,
              const hp::QCollection<dim - 1>   &fq)
        : fe_values(mapping,
                    fe,
                    q,
                    update_values | update_gradients | update_JxW_values |
                      update_quadrature_points)
        , face_values(mapping,
                      fe,
                      fq,
                      update_values | update_gradients | update_JxW_values |
                        update_quadrature_points | update_normal_vectors)
        , reference_values(reference_mapping, fe, q, update_quadrature_points)
        , reference_face_values(reference_mapping,
                                fe,
                                fq,
                                update_quadrature_points)
      {}
      Scratch(const Scratch &o)
        : Scratch(o.fe_values.get_mapping_collection(),
                  o.reference_values.get_mapping_collection(),
                  o.fe_values.get_fe_collection(),
                  o.fe_values.get_quadrature_collection(),
                  o.face_values.get_quadrature_collection())
      {}

      hp::FEValues<dim>           fe_values;
      hp::FEFaceValues<dim>       face_values;
      hp::FEValues<dim>           reference_values;
      hp::FEFaceValues<dim>       reference_face_values;
      std::vector<Tensor<2, dim>> B; ///< A : grad phi_i, per shape function
      PointStates<dim>            states;
      PointTerms<dim>             terms;
    };

    struct CopyData
    {
      FullMatrix<double>                   matrix;
      dealii::Vector<double>               residual;
      std::vector<types::global_dof_index> dofs;
      bool                                 admissible = true;
      double energy = 0; ///< static potential energy of the cell
    };
  } // namespace internal
  using namespace internal;



  template <int dim>
  class ElasticitySimulator<dim>::Impl
  {
  public:
    Impl(const ElasticityParameters &p, const MPI_Comm comm);

    void
    run(RunContext *context);

    // setup
    void
    build_loads();
    void
    setup_system();
    /// (Re)build the Jacobian's sparsity pattern: the mesh's couplings and
    /// those of the IPC contact candidates.
    void
    build_jacobian_pattern();
    /// Static problems without IPC: throw, naming the part, if a part of
    /// `mesh` (with the parts in deformable contact with it) has neither
    /// rigid contact nor Dirichlet conditions on every component. A
    /// necessary condition only: it sees translations, not rotations.
    void
    check_parts_are_held(const Triangulation<dim> &mesh) const;
    void
    make_constraints(const double time);
    void
    compute_null_space();

    void
    setup_shape();
    /// Shape constraints that keep coincident vertex copies together.
    void
    tie_separated_vertices();
    void
    reset_physical_parameters(const std::string &bodies);

    /// The material law of a cell (its body, its Lame pair).
    Material<dim>
    cell_material(
      const typename DoFHandler<dim>::active_cell_iterator &c) const;

    // Forms (the force terms of the residual; adjoint/form.h).
    /// Build the forms of the problem (once: they refer to members).
    void
    setup_forms();
    /// The forms of Loads/Additional forms, from the registry.
    void
    add_registered_forms();
    /// The state fields the forms read (Form::Needs).
    unsigned int
    form_needs() const;
    /// Whether the form takes part now (transient-only forms need a
    /// transient state).
    bool
    form_active(const Form<dim> &f) const;
    /// Whether a point-term form acts on boundary `id`.
    bool
    loaded(const types::boundary_id id) const;
    /// The point states of a cell (face: `face` < faces per cell) from
    /// `fv` (the current shape) and the reference values (material
    /// coordinates); the fields the forms need with `for_forms`, else
    /// grad u and the coordinates only.
    void
    fill_states(const typename DoFHandler<dim>::active_cell_iterator &cell,
                const FEValuesBase<dim>                              &fv,
                const unsigned int                                    face,
                Scratch<dim>                                         &s,
                const bool for_forms = true) const;
    /// Zeroed point terms for `n` points.
    static void
    reset_terms(PointTerms<dim>   &t,
                const unsigned int n,
                const bool         tangent,
                const bool         old_tangent,
                const bool         energy);

    // solving
    bool
    assemble(const Vector_t &u_owned, const bool with_matrix, Vector_t *raw);
    /// One cell's residual (and Jacobian, energy) from the forms' point
    /// terms, its loaded boundary faces included.
    void
    assemble_cell(const typename DoFHandler<dim>::active_cell_iterator &cell,
                  Scratch<dim>                                         &s,
                  CopyData                                             &c,
                  const bool with_matrix,
                  const bool energy) const;
    /// Contract the point terms in `s.terms` with the shape functions.
    static void
    contract_cell_terms(const FEValues<dim> &fv,
                        Scratch<dim>        &s,
                        CopyData            &c,
                        const bool           with_matrix);
    void
    assemble_faces(const typename DoFHandler<dim>::active_cell_iterator &cell,
                   Scratch<dim>                                         &s,
                   CopyData                                             &c,
                   const bool with_matrix,
                   const bool energy) const;
    std::pair<unsigned int, unsigned int>
    newton(const double time, const std::string &where);
    /// The forms' state moves to `state` (along `step`): IPC candidates;
    /// the Jacobian's pattern grows if a form asks.
    void
    update_form_states(const Vector_t &state, const Vector_t *step);
    /// The largest fraction of `step` the forms allow (CCD), with a gap.
    double
    forms_max_step(const Vector_t &state, const Vector_t &step, double gap);
    /// The Dirichlet values of time t on u; with IPC, checks that they do
    /// not carry a boundary into contact, and updates the candidates.
    void
    apply_prescribed_motion(const double t, const std::string &where);
    /// Backtracking line search from u along du, starting at `max_step`:
    /// the potential energy's Armijo condition where the forms have one,
    /// else the residual norm's decrease. On success u moves, `norm` is its
    /// residual norm and the step is returned; none if none is accepted.
    std::optional<double>
    line_search(const Vector_t &du,
                const double    max_step,
                const double    tolerance,
                double         &norm);
    /// Component (0..dim-1) of every locally owned DoF.
    std::vector<unsigned int>
    owned_components() const;
    void
    solve_static();
    void
    solve_transient();
    /// Zero or given initial state, step 0's record and output; `n`: the
    /// step count for the progress line (empty: not known in advance).
    void
    set_initial_state(const std::string &n);
    /// u, v of Initial conditions (and their design offsets).
    void
    interpolate_initial_state();
    /// Step i of `time_grid` from the history: Newton on the BDF residual,
    /// then v^i. Returns the Newton and linear iterations.
    std::pair<unsigned int, unsigned int>
    take_step(const unsigned int i);
    /// Step i accepted: history, stored states, record, output.
    void
    accept_step(const unsigned int                           i,
                const std::pair<unsigned int, unsigned int> &its);
    /// Time/Integrator = adaptive: error-controlled steps to End time.
    void
    solve_adaptive();
    /// Estimated local error of step i in units of the tolerance, for
    /// BDF-q; `own_order`: u^i was computed with order q.
    double
    local_error(const unsigned int i,
                const unsigned int q,
                const bool         own_order) const;
    /// Variable order: the next step's order after step i at order q with
    /// error err, and its step factor.
    std::pair<unsigned int, double>
    next_order(const unsigned int i,
               const unsigned int q,
               const double       err) const;
    /// IPC: h capped by the CCD bound of the free flight from the last step.
    double
    cap_step_by_contact(const double h, const double h_min);
    /// Flag cells by `estimated_error` as Finite element/Marking says;
    /// with `level_limits` within [base_level, top_level].
    void
    mark_cells(const bool level_limits);
    /// Hanging DoFs take their masters' values (Dirichlet values kept).
    void
    constrain_hanging_nodes(std::vector<Vector_t *> vectors) const;
    /// Settle the flags (p4est balance); whether any rank's cells change.
    bool
    mesh_will_change() const;
    /// Kelly's indicators of u_ghost (plus the contact residual where
    /// Contact residual says so) into `estimated_error`.
    void
    kelly_indicators();
    /// Refine and coarsen flags by `eta` (Marking, Refine fraction).
    void
    flag_cells(const Vector<float> &eta, const double coarsen_fraction);
    /// Static adaptive cycles: estimate, mark and refine.
    void
    refine_mesh();
    /// Kelly with contact: add each cell's contact face residual
    /// (Finite element/Contact residual) to the indicators `eta`.
    void
    add_contact_residuals(Vector<float> &eta) const;
    /// Transient adaptivity: the Kelly indicators of u and v, each over its
    /// global norm, summed into `estimated_error`; false if both vanish.
    bool
    transient_indicators();
    /// Transient adaptivity: level limits, and Adaptive cycles refinements
    /// of the initial state.
    void
    start_mesh_adaptation();
    /// Whether the mesh adapts after accepted step i.
    bool
    adapts_after(const unsigned int i) const;
    /// Whether accepted step i ends the run.
    bool
    last_step(const unsigned int i) const;
    /// Refine and coarsen after step i, carrying u, v and every history
    /// level to the new mesh.
    void
    adapt_mesh_in_time(const unsigned int i);
    /// The system on a new mesh (DoFs, constraints, pattern, solvers).
    void
    setup_mesh_dependents();
    /// Error indicator = goal: the dual-weighted residual indicators of the
    /// goal objective into `estimated_error` (|eta_K|); returns J(u_h) and
    /// the signed estimate of J(u) - J(u_h). The state is kept.
    std::pair<double, double>
    estimate_goal_error();
    /// dPhi/dI (times the term weights) of J at the static state, and
    /// J's integral terms there.
    std::vector<std::vector<double>>
    goal_weights(const Objective<dim> &J, double &value);
    /// The adjoint lambda = -z of J at u on the current space, with dJ/du
    /// and J; leaves the Jacobian and `residual` at u assembled.
    Vector_t
    goal_adjoint(const Objective<dim> &J, Vector_t &dJ_du, double &value);
    /// assemble() for the goal estimate: an inverted element is an error.
    void
    assemble_or_throw(const Vector_t &state, const bool with_matrix);
    /// z - I_h z on a cell, as a matrix on its DoF values (goal estimate).
    using LocalInterpolation = std::function<const FullMatrix<double> *(
      const typename DoFHandler<dim>::active_cell_iterator &)>;
    /// The cells' shares of the primal and adjoint residual products with
    /// weights z and v (or, with `interpolation`, their z - I_h z on each
    /// cell, then into `estimated_error`); returns their signed sum (see
    /// goal_estimate.cc).
    double
    share_products(const Vector_t           &h,
                   const Vector_t           &z,
                   const Vector_t           &dual,
                   const Vector_t           &v,
                   const LocalInterpolation &interpolation);
    /// The highest degree the solve uses (the goal estimate's extra element
    /// aside).
    unsigned int
    solve_degree() const
    {
      return p.adaptivity == "hp" ? p.max_degree : p.degree;
    }

    // postprocessing
    void
    record_step(const unsigned int step,
                const double       time,
                const unsigned int newton_its,
                const unsigned int linear_its);
    void
    write_output(const unsigned int step, const double time);
    void
    print_progress(const std::string &head) const;
    /// `raw` (unconstrained cell residuals) tested with the conforming basis
    /// functions: hanging DoFs' entries moved to their masters.
    Vector_t
    conforming_residual(const Vector_t &raw) const;
    void
    compute_reactions();
    Tensor<1, dim>
    point_value(const Point<dim> &p) const;

    // adjoint layer (adjoint.cc)
    void
    build_design_layout();
    /// The starting shape design (Design/Shape perturbation) per shape DoF.
    std::vector<double>
    shape_start() const;
    /// Design/Start: other starting values of the blocks.
    void
    apply_start_values();
    void
    apply_design(const std::vector<double> &q);
    /// After a mesh change (`change` names it in messages) and
    /// build_design_layout(): the blocks that do not live on the mesh take
    /// their entries in `old` (laid out as `old_layout`); shape blocks keep
    /// their start, and so do blocks per cell if `cells_carried`.
    void
    carry_design(const DesignLayout        &old_layout,
                 const std::vector<double> &old,
                 const std::string         &change,
                 const bool                 cells_carried);
    void
    solve_forward(const bool quiet);
    void
    set_step_state(const unsigned int i);
    std::vector<std::vector<double>>
    objective_integrals(const Objective<dim> &J, const unsigned int i);
    double
    objective_value(const Objective<dim> &J);
    /// One pass over the cells for an objective (objective_pass.cc).
    class ObjectivePass;
    /// Objective integrals (no outputs), dJ/du and dJ/dm (`weights`,
    /// `dJ_du`) or the forms' point-term products p^T dh/dm (`adjoint`)
    /// at the current step state; products go to `physical`.
    void
    accumulate(const Objective<dim>                   &J,
               const std::vector<std::vector<double>> *weights,
               const Vector_t                         *adjoint,
               Vector_t                               *dJ_du);
    /// Add the shape products p^T dh/dx theta of the forms' point terms at
    /// a cell (the transport of eq. 3.24) to `local_shape`; `s.states`
    /// holds the cell's state, `sv` the shape field's values.
    void
    add_transport_products(const FEValuesBase<dim> &fv,
                           const FEValuesBase<dim> &sv,
                           const PointAdjoint<dim> &adj,
                           Scratch<dim>            &s,
                           dealii::Vector<double>  &local_shape) const;
    /// The forms' global products (contact) with adjoint `lambda`; lagged
    /// terms go to `lagged` (transient) when given.
    void
    global_products(const Vector_t &lambda, Vector_t *lagged);
    /// The forms' history terms of level i: M z + sum over the later steps
    /// k whose damping rate reads u^i of (d h_k / d u^i)^T lambda_k (none
    /// if `lambda` is null), condensed with `constraints`.
    void
    history_products(const Vector_t                  &z,
                     const std::vector<Vector_t>     *lambda,
                     const unsigned int               i,
                     const AffineConstraints<double> &constraints,
                     Vector_t                        &result);
    /// The damping's strain-rate history of step k >= 1, `level(j)` being
    /// u^{k-j}: u_old = u^{k-1} and the step h_k (backward difference, as
    /// the thesis), or u_old = -sum_j alpha_j u^{k-j} and beta h_k
    /// (Material/Damping rate = bdf). Returns the rate's step.
    double
    damping_rate_history(
      const unsigned int                                   k,
      const std::function<const Vector_t &(unsigned int)> &level,
      Vector_t                                            &u_old) const;
    /// How much step k's damping rate weighs u^{k-j} (0 if it does not).
    double
    damping_rate_weight(const unsigned int k, const unsigned int j) const;
    /// Solve for the static adjoint: the stored Newton Jacobian where every
    /// form's is exact and symmetric, else one assembled for it.
    void
    solve_static_adjoint(const Vector_t &rhs, Vector_t &lambda);
    /// Assemble the transposed exact Jacobian of stored step i.
    void
    assemble_adjoint_jacobian(const unsigned int i, const bool transpose);
    double
    compute_gradient(const Objective<dim> &J, std::vector<double> &dJ);
    /**
     * The backward BDF sweep of a transient adjoint: the forms' products
     * into the physical parameters' sensitivities, dJ/du^0 and dJ/dv^0 into
     * the initial conditions'. `weights_at_step(i)` gives dJ/dI at step i
     * (and adds J's value), `contact_partials(i)` adds the contact force
     * terms' partials to `dJ_du`.
     */
    void
    transient_adjoint(
      const Objective<dim> &J,
      const std::function<std::vector<std::vector<double>>(unsigned int)>
                                              &weights_at_step,
      const std::function<void(unsigned int)> &contact_partials,
      Vector_t                                &dJ_du);
    /// dJ/dq from the sensitivities of the physical parameters.
    void
    chain_to_design(std::vector<double> &dJ) const;
    /// The regularization terms of J (weighted, in term order; zero for
    /// other terms), their gradient added to the sensitivities when
    /// `with_gradient`.
    std::vector<double>
    regularization(const Objective<dim> &J, const bool with_gradient);

    const ElasticityParameters p;
    const MPI_Comm             comm;
    RunContext                *context = nullptr;

    std::unique_ptr<parallel::TriangulationBase<dim>> tria;
    bool                                              simplex = false;
    hp::FECollection<dim>                             fe;
    hp::QCollection<dim>                              quadrature;
    hp::QCollection<dim - 1>                          face_quadrature;
    hp::MappingCollection<dim>                        mapping;
    DoFHandler<dim>                                   dof_handler;
    IndexSet                                          owned, relevant;
    AffineConstraints<double>      constraints_zero, constraints_bc;
    TrilinosWrappers::SparseMatrix jacobian;
    Vector_t                       u, u_ghost, residual;
    Vector_t                       w_ghost, u_old_ghost, v; // transient state
    std::deque<Vector_t>           u_history, v_history;    // [0] = step i-1

    std::map<types::material_id, MaterialProperties> bodies;  ///< as given
    std::set<types::material_id>                     all_ids; ///< of the mesh
    std::map<types::material_id, MaterialProperties>
    parse_bodies(const std::string &text, const std::string &entry) const;
    std::map<std::string, double> constants;
    struct Dirichlet
    {
      types::boundary_id                   id;
      std::vector<bool>                    mask;
      std::shared_ptr<FunctionParser<dim>> function;
    };
    std::vector<Dirichlet> dirichlet;
    std::vector<
      std::pair<types::boundary_id, std::shared_ptr<FunctionParser<dim>>>>
                                         tractions, pressures;
    std::shared_ptr<FunctionParser<dim>> body_force;
    Tensor<1, dim>                       gravity;
    std::vector<Point<dim>>              points;

    // Shape field (thesis ch. 3.7.1): a vector Q1/P1 field holding the
    // positions of the design; the mapping of every integral reads it.
    // Shape designs are offsets from the mesh vertices (shape_reference,
    // mesh_mapping). Loads, boundary values and targets are functions of
    // the material coordinates of the mesh as read (material_positions,
    // reference_mapping): the same field until a remesh, then the material
    // coordinates carried over to the new vertices.
    std::unique_ptr<FESystem<dim>> shape_fe;
    DoFHandler<dim>                shape_dof_handler;
    IndexSet                       shape_owned, shape_relevant;
    AffineConstraints<double>      shape_constraints; ///< hanging + fixed
    Vector_t                       shape_reference; ///< mesh vertices, ghosted
    Vector_t                       shape_ghost;     ///< design x, ghosted
    Vector_t                   material_positions;  ///< X at vertices, ghosted
    hp::MappingCollection<dim> mesh_mapping, reference_mapping;
    /// After a remesh: material coordinates by vertex position, sorted.
    std::vector<std::pair<Point<dim>, Point<dim>>> material_of_vertex;
    unsigned int                                   n_remeshes = 0;
    /// The mesh is a remeshed design (no Shape perturbation applies).
    bool remeshed = false;

    // Remeshing (remesh.cc).
    /// Smallest scaled Jacobian det J / prod |J e_k| over the quadrature
    /// points of the current shape (and where, on the mesh as read).
    double
    min_scaled_jacobian(Point<dim> *where = nullptr) const;
    /// Where the shape's quality is checked: the quadrature points, and
    /// with `guard_corners` the cells' corners too.
    hp::QCollection<dim>
         quality_points() const;
    bool guard_corners = p.design.check_corners;
    /// f(cell, Cauchy stress, JxW) at every quadrature point of the locally
    /// owned cells in the last state.
    void
    for_each_stress(const std::function<
                    void(const typename DoFHandler<dim>::active_cell_iterator &,
                         const Tensor<2, dim> &,
                         double)> &f);
    /// Without the `removed` cells (by active cell index), whose faces
    /// to kept cells become boundary `open_id`.
    RegionBoundaries<dim>
    region_boundaries(const std::vector<bool> *removed = nullptr,
                      types::boundary_id       open_id = 0) const;
    /// Design/Remesh boundary size and feature angle, with the fixed
    /// boundaries and bodies kept.
    BoundaryResampling
    boundary_resampling() const;
    /// Material coordinates at points of the current shape.
    std::vector<Point<dim>>
    material_points(const std::vector<Point<dim>> &x) const;
    /// A Gmsh mesh of the current design that passes Design/Min scaled
    /// Jacobian (else throws); kept for the design it was made for.
    /// With `removed` cells: a one-off mesh, not kept.
    std::string
                        new_mesh(const std::vector<bool> *removed = nullptr,
                                 types::boundary_id       open_id = 0);
    std::string         pending_mesh;
    std::vector<double> pending_design;
    std::pair<double, double> pending_quality; ///< min scaled J: now, new
    types::global_cell_index  pending_size = 0;
    /// Take over `serial` (a mesh_regions() mesh as read) whose vertices
    /// have the material coordinates `X`; keeps the non-shape design. The
    /// mesh it replaces is kept for undo_remesh().
    void
    replace_mesh(const Triangulation<dim>      &serial,
                 const std::vector<Point<dim>> &X);
    /// Back to the mesh and design before the last replace_mesh().
    void
    undo_remesh();
    /// Make `new_tria` the mesh (material coordinates by vertex, sorted;
    /// empty for the mesh as read) and set up on it; the old mesh goes to
    /// `old_tria` first.
    void
    adopt_mesh(std::unique_ptr<parallel::TriangulationBase<dim>>  new_tria,
               std::vector<std::pair<Point<dim>, Point<dim>>>   &&vertex_map,
               std::unique_ptr<parallel::TriangulationBase<dim>> &old_tria);
    /// The mesh before the last replace_mesh(), until commit_remesh(): a
    /// new mesh on which the design cannot be solved is rolled back to it.
    struct PreviousMesh
    {
      std::unique_ptr<parallel::TriangulationBase<dim>> tria;
      std::vector<std::pair<Point<dim>, Point<dim>>>    material_of_vertex;
      bool                                              remeshed = false;
      std::vector<double>                               design;
      std::vector<std::vector<std::string>>             refinements;
    };
    std::unique_ptr<PreviousMesh> previous_mesh;

    // Refinement of a design (design_refinement.cc).
    /// Refine the active cells named in `cells` (CellId strings) and carry
    /// the design over; the shape and blocks per cell are interpolated.
    void
    refine_design_cells(const std::set<std::string> &cells);
    /// Throws unless the design refines in place: a p4est mesh, a static
    /// problem without IPC, no design block per DoF.
    void
    check_refinable() const;
    /// material_of_vertex of the locally owned cells from the material
    /// coordinates `material` (a shape field, owned entries).
    void
    rebuild_material_of_vertex(const Vector_t &material);
    /// The design's entries per cell of the blocks with entries per cell,
    /// by CellId, for the cells after a refinement.
    std::map<std::string, std::vector<double>>
    design_by_cell() const;
    void
    set_design_by_cell(
      const std::map<std::string, std::vector<double>> &by_cell);
    /// The refinements since the mesh as read or last remeshed (CellIds).
    std::vector<std::vector<std::string>> refinements;
    /// While the layout is rebuilt after a refinement: the shape design
    /// per shape DoF (the offsets interpolated at the new vertices).
    std::vector<double> carried_shape;

    // Harmonic extension of boundary shape moves into the interior
    // (Design/Shape parameterization = boundary), rebuilt with the design.
    std::unique_ptr<HarmonicExtension<dim>> extension;

    // The physical parameters forms read and parameterizations set: Lame
    // pairs and damping per cell, load scales, the shape, IPC friction,
    // initial-condition offsets (adjoint/physical_parameters.h).
    PhysicalParameters    physical;
    CellLame             *cell_lame    = nullptr;
    CellDamping          *cell_damping = nullptr;
    LoadScales           *load_scales  = nullptr;
    ShapeField<dim>      *shape_field  = nullptr;
    FrictionCoefficients *friction     = nullptr; ///< IPC runs
    InitialConditions    *initial      = nullptr; ///< transient runs
    /// Size the physical parameters to the mesh (after setup_system()).
    void
    size_physical_parameters();

    // The forms in assembly order; typed views of the elastic and IPC
    // forms (objective integrands read materials, contact force terms the
    // barrier).
    std::vector<std::unique_ptr<Form<dim>>> forms;
    const ElasticForm<dim>                 *elastic_form = nullptr;
    ipc::IpcContactForm<dim>               *ipc_form     = nullptr;

    /// Design/Bodies (default: all material ids).
    std::vector<types::material_id> design_bodies;

    // Design vector layout (one parameterization per block) and the
    // states an adjoint pass reads.
    DesignLayout                                        layout;
    std::vector<std::unique_ptr<Parameterization<dim>>> parameterizations;
    std::vector<double>                                 design;
    bool                                                store_states = false;
    std::vector<Vector_t>                 u_states, v_states; ///< per step
    std::vector<Vector_t>                 reference_states;   ///< target run
    std::shared_ptr<const Objective<dim>> objective;
    bool                                  transpose_matrix = false;
    bool                                  quiet            = false;
    double potential_energy = 0; ///< of the last static assembly
    bool   prepared         = false;
    std::vector<std::vector<double>> objective_cache; ///< last integrals
    double                           memory_of_states = 0;
    /// Static adaptive cycles with contact: each cycle's contact statistics.
    std::vector<nlohmann::json> cycle_contact;
    std::vector<double>         term_values; ///< weighted terms of the last J
    double                      adjoint_seconds = 0, forward_seconds = 0;
    double       adjoint_solve_seconds = 0; ///< part of adjoint_seconds
    unsigned int forward_solves = 0, gradients = 0;

    LinearSolver linear_solver;
    /// Linear solver = cg-mg: the Jacobian is never assembled; assemble()
    /// hands the forms' tangents to this solver instead.
    std::unique_ptr<MatrixFreeElasticity<dim>> matrix_free;
    /// A form reported a boundary-face tangent, which cg-mg cannot apply.
    mutable std::atomic<bool> face_tangent_missed{false};
    /// Solve J x = b with the Jacobian of the last assembly (cg-mg, or the
    /// linear solver; `reuse`: its preconditioner, for an adjoint).
    unsigned int
    solve_jacobian(Vector_t &x, const Vector_t &b, const bool reuse = false);

    // Smoothed penalty contact and friction (Contact section; thesis ch. 2).
    PenaltyContact<dim> contact;
    nlohmann::json      contact_statistics; ///< of the last recorded state

    // Incremental potential contact (IPC section; thesis ch. 3.6-3.7).
    std::unique_ptr<ipc::IpcContact<dim>> ipc_contact;
    /// DoFs whose constraints every rank needs: locally relevant ones and
    /// the collision mesh's (contact couples DoFs of any rank).
    IndexSet constraint_lines;
    /// IPC state of the last Newton solve: line searches cut by CCD, and
    /// over the run the smallest distance and the inverted elements.
    unsigned int ccd_limited_steps = 0;
    double       run_min_distance  = std::numeric_limits<double>::max();
    unsigned int inverted_elements = 0;
    /// The automatic barrier stiffness, scaled on the first call.
    void
    prepare_ipc_stiffness();
    /// Contact state of the last solve for the progress line (and
    /// last_ipc_step); empty without IPC.
    std::string
                   ipc_progress();
    nlohmann::json last_ipc_step;
    /// Step timing for the contact statistics.
    Timer          step_timer;
    nlohmann::json last_timings;
    double         last_assembly_seconds = 0, last_solver_seconds = 0;
    /// IPC friction coefficients of the problem (the reference run's).
    std::vector<double> problem_friction;
    /// Adjoint with IPC: the unprojected contact Hessian (A^c) in assemble().
    bool exact_contact_hessian = false;
    /// Move the collision mesh to the current shape (`where` names it in
    /// errors).
    void
    update_ipc_geometry(const std::string &where);
    /// The `contact force` terms of J at stored step i, times the step
    /// weight sw (per term, zero for others); with dJ_du, add their
    /// partials (state, shape).
    std::vector<double>
    contact_force_terms(const Objective<dim> &J,
                        const unsigned int    i,
                        const double          sw,
                        Vector_t             *dJ_du);
    /// Slip smoothing eps_v dt of IPC friction (static: per load step).
    double
    ipc_friction_eta() const;
    /// Whether the IPC run has friction (coefficients or a friction design).
    bool
    ipc_friction() const;
    /// Whether the Newton line search may use the potential as merit:
    /// static problems, and transient ones with IPC.
    bool
    potential_merit() const;

    // State read by assemble().
    bool   transient      = false;
    double time           = 0;
    double dt             = 0;
    double inertia_factor = 0; ///< 1 / (beta dt)^2
    double rate_dt        = 0; ///< the damping rate's step (PointStates::dt)
    /// The levels of the last transient run (the adjoint's and the
    /// objective's too); frozen: later runs reuse it (Taylor tests,
    /// target trajectories) instead of choosing adaptive steps again.
    TimeGrid     time_grid;
    bool         time_grid_frozen   = false;
    unsigned int rejected_steps     = 0; ///< adaptive steps redone
    double       u_scale            = 0; ///< adaptive: largest |u|_max so far
    double       absolute_tolerance = 0; ///< adaptive, in length units
    unsigned int step_index         = 0; ///< level of set_step_state()
    double       force_scale = 0; ///< largest initial residual seen (tolerance)

    std::vector<typename ElasticitySimulator<dim>::StepRecord>  steps;
    std::vector<typename ElasticitySimulator<dim>::CycleRecord> cycles;
    std::map<types::boundary_id, Tensor<1, dim>>                reactions;
    double max_von_mises = 0, max_frobenius = 0;
    std::vector<std::pair<double, std::string>> pvd_records;
    std::function<void(unsigned int)>           cycle_callback;
    Vector<float>                               estimated_error;
    /// Transient adaptivity (Adaptivity = h on a transient problem): the
    /// level range cells stay in, and the adaptations so far.
    bool         transient_adaptivity = false;
    unsigned int base_level           = 0;
    unsigned int top_level            = 0;
    unsigned int mesh_adaptations     = 0;
    /// Error indicator = goal: the objective refinement aims at.
    std::shared_ptr<const Objective<dim>> goal;
    double assembly_seconds = 0, solver_seconds = 0;
  };



} // namespace forma

#endif
