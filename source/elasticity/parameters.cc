#include <forma/adjoint/form.h>
#include <forma/elasticity/parameters.h>
#include <forma/physics/time_grid.h>

namespace forma
{
  using namespace dealii;

  namespace
  {
    /// The `Finite element` section.
    void
    declare_finite_element(ParameterHandler &prm)
    {
      prm.enter_subsection("Finite element");
      prm.declare_entry(
        "Degree",
        "1",
        Patterns::Integer(1, 4),
        "Polynomial degree: Q1-Q4 on quads/hexes, P1-P2 on "
        "simplices. With Adaptivity = hp, the starting degree.");
      prm.declare_entry(
        "Adaptivity",
        "none",
        Patterns::Selection("none|h|hp"),
        "none: uniform mesh. h: Kelly-indicator refinement with "
        "hanging nodes. hp: the same indicator, with smooth cells "
        "(Legendre coefficient decay) raised in degree instead of "
        "split (static problems). Quads/hexes only. Static problems "
        "solve, estimate and refine Adaptive cycles times; transient "
        "problems (h) refine and coarsen the mesh every Adapt every "
        "steps during the run, carrying every BDF history level to the "
        "new mesh.");
      prm.declare_entry(
        "Error indicator",
        "kelly",
        Patterns::Selection("kelly|goal"),
        "What Adaptivity = h or hp refines by. kelly: gradient jumps across "
        "faces. goal: the dual-weighted residual of Objective/Terms (the "
        "residual of u_h weighted by z - I_h z, z the objective's adjoint "
        "one degree higher); each cycle reports J_h and the estimate of "
        "J - J_h.");
      prm.declare_entry(
        "Contact residual",
        "true",
        Patterns::Bool(),
        "Error indicator = kelly with Contact/Rigid-deformable boundaries: "
        "add to each cell's indicator the residual of its contact faces, "
        "h/24 int |sigma n + t|^2 / (lambda + 2 mu)^2 (t the penalty "
        "traction: sigma n = -t holds for the exact solution), so that "
        "the edge of the contact zone is refined where Kelly, which sees "
        "no boundary faces, would not.");
      prm.declare_entry("Goal estimate",
                        "false",
                        Patterns::Bool(),
                        "Report J(u_h) and the dual-weighted residual "
                        "estimate of J(u) - J(u_h) for Objective/Terms after "
                        "every adaptive cycle, whatever the Error indicator "
                        "(always on with Error indicator = goal).");
      prm.declare_entry("Max degree",
                        "4",
                        Patterns::Integer(1, 4),
                        "Highest degree p-adaptivity may reach.");
      prm.declare_entry(
        "Adaptive cycles",
        "0",
        Patterns::Integer(0, 20),
        "Number of solve-estimate-refine cycles after the first "
        "solve (transient problems: refinements of the "
        "initial state before the first step).");
      prm.declare_entry("Refine fraction",
                        "0.3",
                        Patterns::Double(0, 1),
                        "Fraction flagged for refinement (of the cells or of "
                        "the error: see Marking).");
      prm.declare_entry("Coarsen fraction",
                        "0.0",
                        Patterns::Double(0, 1),
                        "Fraction flagged for coarsening (see Marking).");
      prm.declare_entry(
        "Marking",
        "cell count",
        Patterns::Selection("cell count|error fraction"),
        "cell count: Refine/Coarsen fraction are fractions of the cells "
        "(largest/smallest indicators). error fraction: fractions of the "
        "summed indicator (the fewest cells carrying Refine fraction of it "
        "are refined, those carrying the smallest Coarsen fraction "
        "coarsened); suits transient runs, where the error moves.");
      prm.declare_entry(
        "Adapt every",
        "10",
        Patterns::Integer(1),
        "Transient problems with Adaptivity = h: refine and coarsen the mesh "
        "every this many accepted time steps, by the Kelly indicators of the "
        "displacement and of the velocity (each relative to its norm). "
        "Adaptive cycles then counts refinements of the initial state before "
        "the first step.");
      prm.declare_entry(
        "Max refinement level",
        "2",
        Patterns::Integer(0, 10),
        "Transient problems with Adaptivity = h: the most levels a cell may "
        "be refined beyond the starting mesh (cells are never coarsened "
        "below it).");
      prm.leave_subsection();
    }



    /// The `Material` section.
    void
    declare_material(ParameterHandler &prm)
    {
      prm.enter_subsection("Material");
      prm.declare_entry("Model",
                        "linear elastic",
                        Patterns::Selection("linear elastic|neo-hookean"),
                        "linear elastic: small strain, sigma = C : eps. "
                        "neo-hookean: compressible, geometrically nonlinear "
                        "(P = mu (F - F^-T) + lambda log(J) F^-T).");
      prm.declare_entry("Plane",
                        "strain",
                        Patterns::Selection("strain|stress"),
                        "2D assumption. Plane stress is available for linear "
                        "elasticity.");
      prm.declare_entry(
        "Damping rate",
        "backward difference",
        Patterns::Selection("backward difference|bdf"),
        "The strain rate of the damping stress: backward difference: (F^i - "
        "F^{i-1}) / dt, as the thesis, first order in time whatever the BDF "
        "order. bdf: the BDF derivative of F (the scheme's own velocity), so "
        "that damped runs keep the BDF order (second order with BDF2, also "
        "on adaptive steps).");
      prm.declare_entry(
        "Bodies",
        "0 : E = 1, nu = 0.3",
        Patterns::Anything(),
        "One record per material id, ';' between records: "
        "'<id> : E = .., nu = .., density = .., damping shear = .., "
        "damping bulk = ..' or with 'lambda = .., mu = ..' instead "
        "of E, nu. density defaults to 1, damping (Brown et al., "
        "Pa s) to 0.");
      prm.leave_subsection();
    }



    /// The `Boundary conditions` section.
    void
    declare_boundary_conditions(ParameterHandler &prm)
    {
      prm.enter_subsection("Boundary conditions");
      prm.declare_entry(
        "Dirichlet",
        "",
        Patterns::Anything(),
        "Prescribed displacements, records '<boundary id> : "
        "<components, e.g. xy> : <one expression per component>' "
        "separated by ';'. Expressions in x, y, (z,) t.");
      prm.declare_entry(
        "Traction",
        "",
        Patterns::Anything(),
        "Tractions per reference area, records '<boundary id> : "
        "<dim expressions>'.");
      prm.declare_entry(
        "Load cases",
        "",
        Patterns::Anything(),
        "Several load cases at once (static): alternative Traction records, "
        "one per case, separated by '|', e.g. '3 : 1, -1 | 3 : -1, -1'. Each "
        "case is solved (and its adjoint) on the same design; the objective "
        "sums the state-dependent terms over the cases, terms of the design "
        "alone (volume, volume bound, assembly, alignment, smoothing) count "
        "once. Empty: the one case of Traction.");
      prm.declare_entry("Pressure",
                        "",
                        Patterns::Anything(),
                        "Pressure on the reference normal (dead load), records "
                        "'<boundary id> : <expression>'.");
      prm.declare_entry(
        "Constants",
        "",
        Patterns::Anything(),
        "Named constants for all expressions, 'L = 2, P = 1e3'.");
      prm.leave_subsection();
    }



    /// The `Loads` section.
    void
    declare_loads(ParameterHandler &prm)
    {
      prm.enter_subsection("Loads");
      prm.declare_entry("Gravity",
                        "",
                        Patterns::Anything(),
                        "Gravitational acceleration, dim components (times the "
                        "density gives the body force). Empty: none.");
      prm.declare_entry(
        "Body force",
        "",
        Patterns::Anything(),
        "Body force per reference volume, dim expressions in x, "
        "y, (z,) t. Empty: none.");
      prm.declare_entry(
        "Additional forms",
        "",
        Patterns::Anything(),
        "Further force terms of the problem, registered by name by the library "
        "or an application: records 'name : key=value, ...' separated by ';'." +
          std::string(FormRegistry<2>::instance().entries().empty() ?
                        " None is registered." :
                        " Registered:\n" +
                          FormRegistry<2>::instance().documentation()));
      prm.leave_subsection();
    }



    /// The `Time` section.
    void
    declare_time(ParameterHandler &prm)
    {
      prm.enter_subsection("Time");
      prm.declare_entry("Problem",
                        "static",
                        Patterns::Selection("static|transient"),
                        "static: equilibrium at t = End time / Load steps * k, "
                        "k = 1..Load steps (loads may depend on t). transient: "
                        "BDF time stepping from t = 0 to End time.");
      prm.declare_entry("End time", "1", Patterns::Double(0), "Final time.");
      prm.declare_entry("Time step",
                        "0.1",
                        Patterns::Double(0),
                        "Transient step size (adaptive: the first step).");
      prm.declare_entry(
        "Integrator",
        "fixed",
        Patterns::Selection("fixed|adaptive"),
        "fixed: BDF with the constant Time step. adaptive: "
        "variable-step BDF (order BDF order, 1-5, or chosen per step with "
        "Variable order) whose steps are accepted when "
        "the estimated local displacement error (Milne's "
        "device, max norm) is below Absolute tolerance + "
        "Tolerance * (largest |u|_max so far); gradients are those of the "
        "accepted steps. With IPC, the CCD bound of the free "
        "flight caps each step.");
      prm.declare_entry("Variable order",
                        "false",
                        Patterns::Bool(),
                        "adaptive: choose each step's BDF order between 1 and "
                        "BDF order from the local error estimates of the "
                        "neighbouring orders (as SUNDIALS' IDA does): "
                        "smooth stretches run at high order with long steps.");
      prm.declare_entry("Tolerance",
                        "1e-4",
                        Patterns::Double(0),
                        "adaptive: relative local error tolerance.");
      prm.declare_entry("Absolute tolerance",
                        "0",
                        Patterns::Double(0),
                        "adaptive: absolute local error tolerance (length). "
                        "0: Tolerance * 1% of the mesh's bounding-box "
                        "diagonal.");
      prm.declare_entry("Minimum time step",
                        "0",
                        Patterns::Double(0),
                        "adaptive: smallest step; a step this short is "
                        "accepted whatever its error. 0: 1e-10 End time.");
      prm.declare_entry("Maximum time step",
                        "0",
                        Patterns::Double(0),
                        "adaptive: largest step. 0: End time.");
      prm.declare_entry("BDF order",
                        "2",
                        Patterns::Integer(1, 6),
                        "Order m of the BDF scheme; the first m-1 steps use "
                        "orders 1..m-1.");
      prm.declare_entry(
        "Load steps",
        "1",
        Patterns::Integer(1),
        "Static load increments (Newton starts from the previous "
        "increment).");
      prm.leave_subsection();
    }



    /// The `Initial conditions` section.
    void
    declare_initial_conditions(ParameterHandler &prm)
    {
      prm.enter_subsection("Initial conditions");
      prm.declare_entry("Displacement",
                        "",
                        Patterns::Anything(),
                        "Initial displacement, dim expressions in x, y, (z). "
                        "Empty: zero.");
      prm.declare_entry("Velocity",
                        "",
                        Patterns::Anything(),
                        "Initial velocity, dim expressions. Empty: zero.");
      prm.leave_subsection();
    }



    /// The `Solver` section.
    void
    declare_solver(ParameterHandler &prm)
    {
      prm.enter_subsection("Solver");
      LinearSolver::Parameters::declare(prm);
      prm.declare_entry(
        "Newton relative tolerance",
        "1e-9",
        Patterns::Double(0),
        "Converged when the residual norm falls below this times "
        "the reference force norm (first residual of the step or "
        "the external load, whichever is larger).");
      prm.declare_entry("Newton absolute tolerance",
                        "1e-12",
                        Patterns::Double(0),
                        "... or below this absolute value.");
      prm.declare_entry(
        "Max Newton iterations",
        "30",
        Patterns::Integer(1),
        "Iterations per step before the run is declared failed.");
      prm.declare_entry("Max line search halvings",
                        "12",
                        Patterns::Integer(0),
                        "Backtracking halvings of a Newton step whose residual "
                        "does not decrease or that inverts an element.");
      prm.leave_subsection();
    }



    /// The `Output` section.
    void
    declare_output(ParameterHandler &prm)
    {
      prm.enter_subsection("Output");
      prm.declare_entry("Write vtu",
                        "true",
                        Patterns::Bool(),
                        "Write VTU files with a PVD time series.");
      prm.declare_entry("Output every",
                        "1",
                        Patterns::Integer(1),
                        "Write every n-th step (the last one always).");
      prm.declare_entry(
        "Points",
        "",
        Patterns::Anything(),
        "Points whose displacement is reported each step and in "
        "summary.json, ';' between points, e.g. '10, 0.5 ; 5, 1'.");
      prm.leave_subsection();
    }
  } // namespace



  void
  ElasticityParameters::declare(ParameterHandler &prm)
  {
    MeshParameters::declare(prm);

    declare_finite_element(prm);
    declare_material(prm);
    declare_boundary_conditions(prm);
    declare_loads(prm);
    declare_time(prm);
    declare_initial_conditions(prm);
    declare_solver(prm);
    declare_output(prm);
    DesignParameters::declare(prm);
    ObjectiveParameters::declare(prm);
  }



  namespace
  {
    /// Reads the `Finite element` section.
    void
    read_finite_element(ParameterHandler &prm, ElasticityParameters &p)
    {
      prm.enter_subsection("Finite element");
      p.degree          = prm.get_integer("Degree");
      p.adaptivity      = prm.get("Adaptivity");
      p.error_indicator = prm.get("Error indicator");
      p.goal_estimate =
        prm.get_bool("Goal estimate") || p.error_indicator == "goal";
      p.contact_residual     = prm.get_bool("Contact residual");
      p.max_degree           = prm.get_integer("Max degree");
      p.adaptive_cycles      = prm.get_integer("Adaptive cycles");
      p.refine_fraction      = prm.get_double("Refine fraction");
      p.coarsen_fraction     = prm.get_double("Coarsen fraction");
      p.marking              = prm.get("Marking");
      p.adapt_every          = prm.get_integer("Adapt every");
      p.max_refinement_level = prm.get_integer("Max refinement level");
      prm.leave_subsection();
    }



    /// Reads the `Material` section.
    void
    read_material(ParameterHandler &prm, ElasticityParameters &p)
    {
      prm.enter_subsection("Material");
      p.model            = constitutive_model_from_string(prm.get("Model"));
      p.plane_stress     = prm.get("Plane") == "stress";
      p.bdf_damping_rate = prm.get("Damping rate") == "bdf";
      p.bodies           = prm.get("Bodies");
      prm.leave_subsection();
    }



    /// Reads the `Boundary conditions` section.
    void
    read_boundary_conditions(ParameterHandler &prm, ElasticityParameters &p)
    {
      prm.enter_subsection("Boundary conditions");
      p.dirichlet  = prm.get("Dirichlet");
      p.traction   = prm.get("Traction");
      p.load_cases = prm.get("Load cases");
      p.pressure   = prm.get("Pressure");
      p.constants  = prm.get("Constants");
      prm.leave_subsection();
    }



    /// Reads the `Loads` section.
    void
    read_loads(ParameterHandler &prm, ElasticityParameters &p)
    {
      prm.enter_subsection("Loads");
      p.gravity          = prm.get("Gravity");
      p.body_force       = prm.get("Body force");
      p.additional_forms = prm.get("Additional forms");
      prm.leave_subsection();
    }



    /// Reads the `Time` section.
    void
    read_time(ParameterHandler &prm, ElasticityParameters &p)
    {
      prm.enter_subsection("Time");
      p.problem                 = prm.get("Problem");
      p.end_time                = prm.get_double("End time");
      p.time_step               = prm.get_double("Time step");
      p.bdf_order               = prm.get_integer("BDF order");
      p.load_steps              = prm.get_integer("Load steps");
      p.time_integrator         = prm.get("Integrator");
      p.variable_order          = prm.get_bool("Variable order");
      p.time_tolerance          = prm.get_double("Tolerance");
      p.absolute_time_tolerance = prm.get_double("Absolute tolerance");
      p.minimum_time_step       = prm.get_double("Minimum time step");
      p.maximum_time_step       = prm.get_double("Maximum time step");
      prm.leave_subsection();
    }



    /// Reads the `Initial conditions` section.
    void
    read_initial_conditions(ParameterHandler &prm, ElasticityParameters &p)
    {
      prm.enter_subsection("Initial conditions");
      p.initial_displacement = prm.get("Displacement");
      p.initial_velocity     = prm.get("Velocity");
      prm.leave_subsection();
    }



    /// Reads the `Solver` section.
    void
    read_solver(ParameterHandler &prm, ElasticityParameters &p)
    {
      prm.enter_subsection("Solver");
      p.linear_solver.parse(prm);
      p.newton_relative_tolerance = prm.get_double("Newton relative tolerance");
      p.newton_absolute_tolerance = prm.get_double("Newton absolute tolerance");
      p.max_newton_iterations     = prm.get_integer("Max Newton iterations");
      p.max_line_search_halvings  = prm.get_integer("Max line search halvings");
      prm.leave_subsection();
    }



    /// Reads the `Output` section.
    void
    read_output(ParameterHandler &prm, ElasticityParameters &p)
    {
      prm.enter_subsection("Output");
      p.write_vtu    = prm.get_bool("Write vtu");
      p.output_every = prm.get_integer("Output every");
      p.points       = prm.get("Points");
      prm.leave_subsection();
    }



    /// The `Time` section's settings agree with each other.
    void
    check_time(const ElasticityParameters &p)
    {
      AssertThrow(p.problem == "static" || p.time_step > 0,
                  ExcMessage(
                    "Time/Time step must be positive for transient runs."));
      AssertThrow(p.time_integrator == "fixed" || p.problem == "transient",
                  ExcMessage("Time/Integrator = adaptive is for transient "
                             "problems (Time/Problem = transient)."));
      AssertThrow(p.time_integrator == "fixed" ||
                    p.bdf_order <= TimeGrid::max_variable_order,
                  ExcMessage("Time/Integrator = adaptive steps with BDF orders "
                             "1 to " +
                             std::to_string(TimeGrid::max_variable_order) +
                             "; set Time/BDF order to at most that (got " +
                             std::to_string(p.bdf_order) + ")."));
      AssertThrow(!p.variable_order || p.time_integrator == "adaptive",
                  ExcMessage("Time/Variable order needs Time/Integrator = "
                             "adaptive."));
      AssertThrow(p.time_integrator == "fixed" || p.time_tolerance > 0,
                  ExcMessage("Time/Integrator = adaptive needs a positive "
                             "Time/Tolerance."));
      AssertThrow(p.time_integrator == "fixed" ||
                    p.minimum_time_step < p.end_time,
                  ExcMessage("Time/Minimum time step must be below Time/End "
                             "time."));
      AssertThrow(p.maximum_time_step == 0 ||
                    p.minimum_time_step <= p.maximum_time_step,
                  ExcMessage("Time/Minimum time step exceeds Time/Maximum time "
                             "step."));
      AssertThrow(p.problem == "static" || p.end_time > 0,
                  ExcMessage(
                    "Time/End time must be positive for transient runs."));
    }



    /// Adaptive refinement agrees with the problem and the mesh.
    void
    check_adaptivity(const ElasticityParameters &p)
    {
      AssertThrow(p.adaptivity != "hp" || p.problem == "static",
                  ExcMessage("Finite element/Adaptivity = hp is for static "
                             "problems; transient problems adapt with h."));
      AssertThrow(!p.goal_estimate || p.problem == "static",
                  ExcMessage("Finite element/Error indicator = goal (or Goal "
                             "estimate) estimates static problems; the "
                             "transient (backward in time) estimate is not "
                             "available yet: use Error indicator = kelly."));
      AssertThrow(p.refine_fraction + p.coarsen_fraction <= 1,
                  ExcMessage("Finite element: Refine fraction + Coarsen "
                             "fraction must not exceed 1."));
      AssertThrow(p.mesh.separate_interfaces.empty() || p.adaptivity == "none",
                  ExcMessage("Mesh/Separate interfaces: adaptive refinement "
                             "is not available on meshes cut open at "
                             "interfaces; set Finite element/Adaptivity = "
                             "none."));
    }



    /// Contact, IPC, load cases and the linear solver combine.
    void
    check_models(const ElasticityParameters &p)
    {
      AssertThrow(p.load_cases.empty() || p.problem == "static",
                  ExcMessage("Boundary conditions/Load cases: several load "
                             "cases are for static problems."));
      AssertThrow(p.contact.empty() || p.problem == "static",
                  ExcMessage("Contact: smoothed penalty contact is a static "
                             "model (thesis ch. 2); set Time/Problem = "
                             "static."));
      AssertThrow(p.contact.deformable.empty() ||
                    !p.mesh.separate_interfaces.empty(),
                  ExcMessage(
                    "Contact/Deformable-deformable: the interfaces come "
                    "from Mesh/Separate interfaces (which cuts them "
                    "open and keeps their two sides together in shape "
                    "designs); set it, e.g. '1-2 : 10'."));
      AssertThrow(p.contact.empty() ||
                    p.model == ConstitutiveModel::linear_elastic,
                  ExcMessage(
                    "Contact: the smoothed penalty model is linearized "
                    "(gaps along the undeformed normal, thesis ch. 2): "
                    "set Material/Model = linear elastic."));
      AssertThrow(p.linear_solver.type != "cg-mg" ||
                    (p.contact.empty() && !p.ipc.enabled &&
                     p.adaptivity != "hp"),
                  ExcMessage("Solver/Linear solver = cg-mg (matrix-free) "
                             "handles elasticity, inertia and damping on one "
                             "polynomial degree; with contact, IPC or hp "
                             "adaptivity use cg-amg, gmres-amg or direct."));
      AssertThrow(p.linear_solver.type != "cg-mg" || p.degree >= 2,
                  ExcMessage(
                    "Solver/Linear solver = cg-mg smooths on Q_p and "
                    "solves on Q1: it needs Finite element/Degree 2, 3 "
                    "or 4 (got 1); for Q1 use cg-amg."));
      AssertThrow(!p.contact.has_friction() || p.linear_solver.type != "cg-amg",
                  ExcMessage(
                    "Contact: friction makes the Jacobian "
                    "unsymmetric; use Solver/Linear solver = direct or "
                    "gmres-amg, not cg-amg."));
      AssertThrow(!p.goal_estimate || p.contact.empty(),
                  ExcMessage(
                    "Finite element/Error indicator = goal (or Goal "
                    "estimate) is not available with contact (the "
                    "dual-weighted residual does not cover the "
                    "penalty's changing active set); use Error "
                    "indicator = kelly, whose Contact residual refines "
                    "the contact zone."));
      AssertThrow(p.contact.rigid_gaps.empty() || !p.design.has("shape"),
                  ExcMessage("Contact/Rigid gaps: shape designs are not "
                             "available with a gap (its shape derivative is "
                             "not implemented); remove shape from Design/"
                             "Parameters or the gap."));
      AssertThrow(!p.ipc.enabled || p.adaptivity == "none",
                  ExcMessage("IPC: adaptive refinement is not available with "
                             "IPC contact yet; set Finite element/Adaptivity = "
                             "none."));
      AssertThrow(!p.ipc.enabled || p.contact.empty(),
                  ExcMessage("IPC and smoothed penalty contact exclude each "
                             "other."));
      AssertThrow(!p.ipc.enabled || p.load_cases.empty(),
                  ExcMessage("IPC: several load cases are not available with "
                             "IPC contact."));
    }



    /// The goal estimate and hp refinement have what they act on.
    void
    check_adaptive_cycles(const ElasticityParameters &p)
    {
      AssertThrow(!p.goal_estimate || p.adaptivity != "none",
                  ExcMessage("Finite element/Error indicator = goal and Goal "
                             "estimate act on adaptive cycles: set Finite "
                             "element/Adaptivity = h or hp."));
      AssertThrow(!p.goal_estimate ||
                    !Utilities::trim(p.objective.terms).empty(),
                  ExcMessage("Finite element/Error indicator = goal (or Goal "
                             "estimate) estimates the error of the objective: "
                             "set Objective/Terms (e.g. 'stress : p=4')."));
      AssertThrow(!p.goal_estimate || p.load_cases.empty(),
                  ExcMessage("Finite element/Error indicator = goal (or Goal "
                             "estimate) is for one load case: clear Boundary "
                             "conditions/Load cases."));
      AssertThrow(
        !p.goal_estimate || p.linear_solver.type != "cg-mg",
        ExcMessage(
          "Finite element/Error indicator = goal (or Goal "
          "estimate) solves the adjoint one degree higher, which cg-mg "
          "(one degree) does not: use direct, cg-amg or "
          "gmres-amg."));
      AssertThrow(p.max_degree >= p.degree || p.adaptivity != "hp",
                  ExcMessage("Finite element/Max degree is below Degree."));
    }
  } // namespace



  void
  ElasticityParameters::parse(ParameterHandler  &prm,
                              const std::string &prm_dir,
                              const bool         with_contact,
                              const bool         with_ipc)
  {
    dim = prm.get_integer("Dimension");
    mesh.parse(prm, prm_dir);
    if (with_contact)
      contact.parse(prm);
    if (with_ipc)
      ipc.parse(prm, dim, prm_dir);
    read_finite_element(prm, *this);
    read_material(prm, *this);
    read_boundary_conditions(prm, *this);
    read_loads(prm, *this);
    read_time(prm, *this);
    read_initial_conditions(prm, *this);
    read_solver(prm, *this);
    read_output(prm, *this);
    design.parse(prm);
    objective.parse(prm);

    check_time(*this);
    check_adaptivity(*this);
    check_models(*this);
    check_adaptive_cycles(*this);
  }
} // namespace forma
