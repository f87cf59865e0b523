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
                      Patterns::Selection("direct|cg-amg|gmres-amg"),
                      "direct: sparse LU (Amesos KLU), robust for small and "
                      "stiff problems. cg-amg: conjugate gradients with "
                      "algebraic multigrid (symmetric problems, large meshes). "
                      "gmres-amg: GMRES with AMG (non-symmetric tangents, e.g. "
                      "with damping).");
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
    SolverControl                                   control{1, 0, false, false};
    std::unique_ptr<TrilinosWrappers::SolverDirect> direct;
    TrilinosWrappers::PreconditionAMG               amg;
    bool                                            has_amg = false;
  };



  LinearSolver::LinearSolver(const Parameters &parameters)
    : state(std::make_shared<State>())
    , parameters(parameters)
  {}



  void
  LinearSolver::set_null_space(std::vector<std::vector<double>> modes)
  {
    n_modes = modes.size();
    null_space.clear();
    for (const auto &m : modes)
      null_space.insert(null_space.end(), m.begin(), m.end());
  }



  unsigned int
  LinearSolver::solve(const TrilinosWrappers::SparseMatrix &A,
                      TrilinosWrappers::MPI::Vector        &x,
                      const TrilinosWrappers::MPI::Vector  &b,
                      const bool                            higher_order) const
  {
    if (parameters.type == "direct")
      {
        try
          {
            state->direct =
              std::make_unique<TrilinosWrappers::SolverDirect>(state->control);
            state->direct->initialize(A);
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

    // ML with the rigid-body modes as near null space: translations and
    // rotations keep the AMG iteration count flat under refinement.
    TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic              = true;
    data.higher_order_elements = higher_order;
    data.smoother_sweeps       = 2;
    data.aggregation_threshold = 0.02;
    Teuchos::ParameterList              list;
    std::unique_ptr<Epetra_MultiVector> distributed_modes;
    data.set_parameters(list, distributed_modes, A);
    std::vector<double> modes = null_space;
    if (n_modes > 0)
      {
        list.set("null space: type", "pre-computed");
        list.set("null space: dimension", static_cast<int>(n_modes));
        list.set("null space: vectors", modes.data());
      }
    TrilinosWrappers::PreconditionAMG &amg = state->amg;
    amg.initialize(A, list);
    state->has_amg = true;

    SolverControl control(parameters.max_iterations,
                          parameters.relative_tolerance * b.l2_norm(),
                          false,
                          false);
    try
      {
        if (parameters.type == "cg-amg")
          {
            SolverCG<TrilinosWrappers::MPI::Vector> cg(control);
            cg.solve(A, x, b, amg);
          }
        else
          {
            SolverGMRES<TrilinosWrappers::MPI::Vector> gmres(
              control,
              SolverGMRES<TrilinosWrappers::MPI::Vector>::AdditionalData(100));
            gmres.solve(A, x, b, amg);
          }
      }
    catch (const SolverControl::NoConvergence &exc)
      {
        AssertThrow(false,
                    ExcMessage("the linear solver '" + parameters.type +
                               "' did not converge in " +
                               std::to_string(exc.last_step) +
                               " iterations (residual " +
                               std::to_string(exc.last_residual) +
                               "); raise 'Max linear iterations' or use the "
                               "direct solver."));
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
    if (parameters.type == "direct")
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
    if (parameters.type == "cg-amg")
      {
        SolverCG<TrilinosWrappers::MPI::Vector> cg(control);
        cg.solve(A, x, b, state->amg);
      }
    else
      {
        SolverGMRES<TrilinosWrappers::MPI::Vector> gmres(
          control,
          SolverGMRES<TrilinosWrappers::MPI::Vector>::AdditionalData(100));
        gmres.solve(A, x, b, state->amg);
      }
    return control.last_step();
  }
} // namespace forma
