#ifndef forma_solvers_linear_solver_h
#define forma_solvers_linear_solver_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <memory>
#include <string>
#include <vector>

namespace forma
{
  /**
   * The linear solvers every forma app offers, chosen in the `Linear solver`
   * section: sparse direct solvers for small or stiff problems (Amesos KLU
   * on one rank, or MUMPS distributed over the ranks), and CG or GMRES
   * preconditioned by ML algebraic multigrid with the rigid-body null
   * space for large ones.
   */
  class LinearSolver
  {
  public:
    struct Parameters
    {
      /// direct | direct-mumps | cg-amg | gmres-amg | cg-mg
      std::string  type               = "direct";
      double       relative_tolerance = 1e-10;
      unsigned int max_iterations     = 2000;

      static void
      declare(dealii::ParameterHandler &prm);
      void
      parse(dealii::ParameterHandler &prm);
    };

    explicit LinearSolver(const Parameters &parameters);

    /// Rigid-body modes (owned entries of each mode) for the AMG null space;
    /// `pde_equations` > 1 lets ML aggregate node-wise groups of that many
    /// consecutive DoFs (see RigidBodyModes).
    void
    set_null_space(std::vector<std::vector<double>> modes,
                   const unsigned int               pde_equations = 1);

    /// Solve A x = b; returns the iteration count (1 for direct).
    unsigned int
    solve(const dealii::TrilinosWrappers::SparseMatrix &A,
          dealii::TrilinosWrappers::MPI::Vector        &x,
          const dealii::TrilinosWrappers::MPI::Vector  &b,
          const bool                                    higher_order) const;

    /**
     * Solve A x = b with the factorization (direct) or AMG hierarchy
     * (iterative) kept from the last solve() as preconditioner: for the
     * adjoint of a converged Newton solve, whose Jacobian differs little
     * from the last factored one. Iterates to the same tolerance; returns
     * the iteration count.
     */
    unsigned int
    solve_reusing(const dealii::TrilinosWrappers::SparseMatrix &A,
                  dealii::TrilinosWrappers::MPI::Vector        &x,
                  const dealii::TrilinosWrappers::MPI::Vector  &b) const;

  private:
    /// Replaces the direct solver's factorization by that of A.
    void
    factorize(const dealii::TrilinosWrappers::SparseMatrix &A) const;

    struct State;
    std::shared_ptr<State> state; ///< last factorization / preconditioner
    Parameters             parameters;
    std::vector<double>    null_space; ///< column-major, n_owned x n_modes
    unsigned int           n_modes       = 0;
    unsigned int           pde_equations = 1;
  };

  /// The message of a Krylov solve that ran out of iterations.
  std::string
  no_convergence_message(const std::string &solver,
                         const unsigned int last_step,
                         const double       last_residual);

  /**
   * ML smoothed aggregation for an elasticity matrix: `modes` (owned
   * entries, one vector per mode; may be empty) as near null space, node-wise
   * aggregation of `pde_equations` DoFs. Shared by LinearSolver and the
   * coarse level of the matrix-free multigrid.
   */
  void
  initialize_elasticity_amg(dealii::TrilinosWrappers::PreconditionAMG    &amg,
                            const dealii::TrilinosWrappers::SparseMatrix &A,
                            const std::vector<std::vector<double>>       &modes,
                            const bool         higher_order,
                            const unsigned int pde_equations);
} // namespace forma

#endif
