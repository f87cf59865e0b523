#ifndef forma_solvers_matrix_free_elasticity_h
#define forma_solvers_matrix_free_elasticity_h

#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_vector.h>

#include <forma/solvers/linear_solver.h>

#include <memory>
#include <string>
#include <vector>

namespace forma
{
  /**
   * `Linear solver = cg-mg`: CG on the Jacobian of a displacement problem
   * without assembling it. The operator applies, cell by cell with
   * deal.II's MatrixFree, the tangent the forms report at every quadrature
   * point (flux tangent dP/dgrad u, source tangent ds/du: elasticity of any
   * law, inertia, damping); a two-level p-multigrid preconditions it:
   * Chebyshev smoothing on Q_p, ML AMG (rigid-body modes, node-wise
   * aggregation) on Q1 assembled from the same tangents on the same mesh.
   * A tangent that is constant on a cell (linear elasticity) is stored
   * once per cell, so memory is the vectors, the mesh data and the Q1 level.
   *
   * Use: reinit() when the mesh, mapping or constraints change; per
   * Newton step set_cell_tangent() for every locally owned cell (from any
   * thread, one cell each), then solve(): CG where every tangent is
   * symmetric, GMRES otherwise (damped Neo-Hookean). Hexahedral or
   * quadrilateral meshes, FE_Q of degree 2 to 4.
   */
  template <int dim>
  class MatrixFreeElasticity
  {
  public:
    explicit MatrixFreeElasticity(const LinearSolver::Parameters &parameters);
    ~MatrixFreeElasticity();

    /// `dof_handler`: FESystem(FE_Q(degree), dim) on every cell (an hp
    /// handler with one active element is fine); `zero_constraints`:
    /// hanging nodes and homogeneous Dirichlet rows of the Newton update.
    void
    reinit(const dealii::Mapping<dim>              &mapping,
           const dealii::DoFHandler<dim>           &dof_handler,
           const dealii::AffineConstraints<double> &zero_constraints,
           const unsigned int                       degree);

    /// The tangent at the quadrature points (QGauss(degree + 1), in
    /// FEValues order) of the cell with this active cell index; an empty
    /// `source_tangent` means none. `transpose`: apply the transposed
    /// Jacobian (adjoints).
    void
    set_cell_tangent(const unsigned int active_cell_index,
                     const std::vector<dealii::Tensor<4, dim>> &flux_tangent,
                     const std::vector<double>                 &source_tangent,
                     const bool transpose = false);

    /// x = A^-1 b to the relative tolerance of the parameters; returns the
    /// CG iteration count. x and b are laid out like `dof_handler`.
    unsigned int
    solve(dealii::TrilinosWrappers::MPI::Vector       &x,
          const dealii::TrilinosWrappers::MPI::Vector &b);

    /// Seconds spent in the last setup of the multigrid (diagonal,
    /// eigenvalue estimate, Q1 matrix, AMG) and in CG.
    std::pair<double, double>
    last_times() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace forma

#endif
