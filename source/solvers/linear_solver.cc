#include <deal.II/base/exceptions.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_solver.h>

#include <forma/base/application.h>
#include <forma/solvers/linear_solver.h>

#include <Epetra_MultiVector.h>
#include <Teuchos_ParameterList.hpp>

namespace forma
{
  using namespace dealii;

  void
  LinearSolver::Parameters::declare(ParameterHandler &prm)
  {
    prm.declare_entry("Linear solver",
                      "direct",
                      Patterns::Selection(
                        "direct|direct-mumps|cg-amg|gmres-amg|cg-mg"),
                      "direct: sparse LU (Amesos KLU, on one rank: the "
                      "matrix is gathered there), robust for small and "
                      "stiff problems. direct-mumps: distributed sparse LU "
                      "(MUMPS through Amesos), the factorization spread over "
                      "the MPI ranks: contact and IPC Jacobians on several "
                      "ranks. cg-amg: conjugate gradients with "
                      "algebraic multigrid (symmetric problems, large meshes). "
                      "gmres-amg: GMRES with AMG (non-symmetric tangents, e.g. "
                      "with damping). cg-mg: conjugate gradients on the "
                      "Jacobian applied without a matrix, preconditioned by "
                      "p-multigrid (Chebyshev smoothing, AMG on Q1): the "
                      "fastest and leanest for large quad/hex meshes of "
                      "degree 2-4 without contact (forma-transient-ipc).");
    prm.declare_entry("Linear tolerance",
                      "1e-10",
                      Patterns::Double(0),
                      "Relative residual reduction of the iterative solvers.");
    prm.declare_entry("Max linear iterations",
                      "2000",
                      Patterns::Integer(1),
                      "Iteration limit of the iterative solvers.");
  }



  void
  LinearSolver::Parameters::parse(ParameterHandler &prm)
  {
    type               = prm.get("Linear solver");
    relative_tolerance = prm.get_double("Linear tolerance");
    max_iterations     = prm.get_integer("Max linear iterations");
  }



  struct LinearSolver::State
  {
    SolverControl control{1, 0, false, false};
    /// MUMPS: its own copy of the factored matrix, which the caller may
    /// reinit (a new IPC pattern) while the factors live on; declared
    /// before `direct` so that the factors are destroyed first.
    std::unique_ptr<TrilinosWrappers::SparseMatrix> factored;
    std::unique_ptr<TrilinosWrappers::SolverDirect> direct;
    TrilinosWrappers::PreconditionAMG               amg;
    bool                                            has_amg = false;
  };



  LinearSolver::LinearSolver(const Parameters &parameters)
    : state(std::make_shared<State>())
    , parameters(parameters)
  {}



  void
  LinearSolver::set_null_space(std::vector<std::vector<double>> modes,
                               const unsigned int               pde_equations)
  {
    n_modes = modes.size();
    null_space.clear();
    for (const auto &m : modes)
      null_space.insert(null_space.end(), m.begin(), m.end());
    this->pde_equations = pde_equations;
  }



  namespace
  {
    void
    initialize_amg(TrilinosWrappers::PreconditionAMG    &amg,
                   const TrilinosWrappers::SparseMatrix &A,
                   std::vector<double>                   modes,
                   const unsigned int                    n_modes,
                   const bool                            higher_order,
                   const unsigned int                    pde_equations)
    {
      // ML with the rigid-body modes as near null space: translations and
      // rotations keep the AMG iteration count flat under refinement.
      TrilinosWrappers::PreconditionAMG::AdditionalData data;
      data.elliptic              = true;
      data.higher_order_elements = higher_order;
      data.smoother_sweeps       = 2;
      // Measured on 3D Q2 elasticity (182k DoFs): 0.02 -> 1e-3 takes CG
      // from 47 to 34 iterations, on the Q1 level of cg-mg from 26 to 13.
      data.aggregation_threshold = 1e-3;
      Teuchos::ParameterList              list;
      std::unique_ptr<Epetra_MultiVector> distributed_modes;
      data.set_parameters(list, distributed_modes, A);
      if (n_modes > 0)
        {
          list.set("null space: type", "pre-computed");
          list.set("null space: dimension", static_cast<int>(n_modes));
          list.set("null space: vectors", modes.data());
        }
      if (pde_equations > 1)
        list.set("PDE equations", static_cast<int>(pde_equations));
      amg.initialize(A, list);
    }
  } // namespace



  void
  initialize_elasticity_amg(TrilinosWrappers::PreconditionAMG      &amg,
                            const TrilinosWrappers::SparseMatrix   &A,
                            const std::vector<std::vector<double>> &modes,
                            const bool         higher_order,
                            const unsigned int pde_equations)
  {
    std::vector<double> flat;
    for (const auto &m : modes)
      flat.insert(flat.end(), m.begin(), m.end());
    initialize_amg(amg, A, flat, modes.size(), higher_order, pde_equations);
  }



  std::string
  no_convergence_message(const std::string &solver,
                         const unsigned int last_step,
                         const double       last_residual)
  {
    return "the linear solver '" + solver + "' did not converge in " +
           std::to_string(last_step) + " iterations (residual " +
           std::to_string(last_residual) +
           "); raise 'Max linear iterations' or use the direct solver.";
  }



  void
  LinearSolver::factorize(const TrilinosWrappers::SparseMatrix &A) const
  {
    // Old factors go before their matrix (MUMPS frees its distributed
    // data through the matrix's communicator).
    state->direct.reset();
    state->factored.reset();
    if (parameters.type == "direct")
      {
        state->direct =
          std::make_unique<TrilinosWrappers::SolverDirect>(state->control);
        state->direct->initialize(A);
        return;
      }
    state->factored = std::make_unique<TrilinosWrappers::SparseMatrix>();
    state->factored->copy_from(A);
    state->direct = std::make_unique<TrilinosWrappers::SolverDirect>(
      state->control,
      TrilinosWrappers::SolverDirect::AdditionalData(false, "Amesos_Mumps"));
    state->direct->initialize(*state->factored);
  }



  unsigned int
  LinearSolver::solve(const TrilinosWrappers::SparseMatrix &A,
                      TrilinosWrappers::MPI::Vector        &x,
                      const TrilinosWrappers::MPI::Vector  &b,
                      const bool                            higher_order) const
  {
    if (parameters.type == "direct" || parameters.type == "direct-mumps")
      {
        try
          {
            factorize(A);
            state->direct->solve(x, b);
          }
        catch (const std::exception &exc)
          {
            state->direct.reset();
            AssertThrow(false,
                        ExcMessage(
                          "the direct linear solver failed (singular "
                          "system? check that the Dirichlet conditions "
                          "remove all rigid-body motions): " +
                          error_message(exc)));
          }
        return 1;
      }

    initialize_amg(
      state->amg, A, null_space, n_modes, higher_order, pde_equations);
    TrilinosWrappers::PreconditionAMG &amg = state->amg;
    state->has_amg                         = true;

    SolverControl control(parameters.max_iterations,
                          parameters.relative_tolerance * b.l2_norm(),
                          false,
                          false);
    try
      {
        if (parameters.type != "gmres-amg")
          {
            SolverCG<TrilinosWrappers::MPI::Vector> cg(control);
            cg.solve(A, x, b, amg);
          }
        else
          {
            SolverGMRES<TrilinosWrappers::MPI::Vector> gmres(
              control,
              SolverGMRES<TrilinosWrappers::MPI::Vector>::AdditionalData(
                100, true /* right preconditioning: true residual */));
            gmres.solve(A, x, b, amg);
          }
      }
    catch (const SolverControl::NoConvergence &exc)
      {
        AssertThrow(false,
                    ExcMessage(no_convergence_message(parameters.type,
                                                      exc.last_step,
                                                      exc.last_residual)));
      }
    return control.last_step();
  }



  unsigned int
  LinearSolver::solve_reusing(const TrilinosWrappers::SparseMatrix &A,
                              TrilinosWrappers::MPI::Vector        &x,
                              const TrilinosWrappers::MPI::Vector  &b) const
  {
    const double tolerance =
      std::max(parameters.relative_tolerance, 1e-12) * b.l2_norm();
    if (parameters.type == "direct" || parameters.type == "direct-mumps")
      {
        if (!state->direct)
          return solve(A, x, b, false);
        // Iterative refinement with the old factors: converges at the rate
        // |I - S^-1 A|, tiny after a converged Newton solve.
        TrilinosWrappers::MPI::Vector r(b), dx(b);
        x = 0;
        for (unsigned int it = 1; it <= 20; ++it)
          {
            A.vmult(r, x);
            r.sadd(-1., 1., b);
            if (r.l2_norm() <= tolerance)
              return it;
            state->direct->solve(dx, r);
            x += dx;
          }
        return solve(A, x, b, false); // old factors too far off
      }
    if (!state->has_amg)
      return solve(A, x, b, true);
    SolverControl control(parameters.max_iterations, tolerance, false, false);
    if (parameters.type != "gmres-amg")
      {
        SolverCG<TrilinosWrappers::MPI::Vector> cg(control);
        cg.solve(A, x, b, state->amg);
      }
    else
      {
        SolverGMRES<TrilinosWrappers::MPI::Vector> gmres(
          control,
          SolverGMRES<TrilinosWrappers::MPI::Vector>::AdditionalData(
            100, true /* right preconditioning: true residual */));
        gmres.solve(A, x, b, state->amg);
      }
    return control.last_step();
  }
} // namespace forma
