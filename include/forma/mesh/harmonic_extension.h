#ifndef forma_mesh_harmonic_extension_h
#define forma_mesh_harmonic_extension_h

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <forma/solvers/linear_solver.h>

#include <functional>
#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class DoFHandler;
  template <int dim, int spacedim>
  class Mapping;
} // namespace dealii

namespace forma
{
  /**
   * Harmonic extension of boundary moves of a vector Q1/P1 field into the
   * interior: the interior entries solve the vector Laplace problem on the
   * mesh as read, A_II x_I = -A_IB x_B (every boundary DoF constrained),
   * factored once. Its transpose pulls a gradient back to the boundary
   * entries. Shape designs of the boundary alone (Design/Shape
   * parameterization = boundary) move the interior vertices this way, which
   * keeps the interior mesh smooth.
   */
  template <int dim>
  class HarmonicExtension
  {
  public:
    using Vector = dealii::TrilinosWrappers::MPI::Vector;

    /// `constraints`: the field's own (fixed and hanging DoFs), applied to
    /// the boundary values; `mapping`: the mesh as read.
    HarmonicExtension(const dealii::DoFHandler<dim, dim>      &dof_handler,
                      const dealii::AffineConstraints<double> &constraints,
                      const dealii::Mapping<dim, dim>         &mapping,
                      const MPI_Comm                           comm);

    /// Replace the interior entries of x by the extension of its boundary
    /// entries.
    void
    extend(Vector &x);

    /// The transpose of extend(): g_B - A_BI A_II^-1 g_I on the boundary
    /// entries, zero in the interior.
    void
    extend_transpose(Vector &g);

    /// Whether DoF i is a boundary entry (a value extend() keeps).
    bool
    is_boundary(const dealii::types::global_dof_index i);

  private:
    void
    setup();

    /// f(cell Laplacian, its DoFs) for every locally owned cell.
    void
    for_each_cell_laplacian(
      const std::function<
        void(const dealii::FullMatrix<double> &,
             const std::vector<dealii::types::global_dof_index> &)> &f) const;

    /// The Laplacian times x, condensed with `c`.
    Vector
    laplacian_times(const Vector                            &x,
                    const dealii::AffineConstraints<double> &c);

    const dealii::DoFHandler<dim, dim>      &dof_handler;
    const dealii::AffineConstraints<double> &constraints;
    const dealii::Mapping<dim, dim>         &mapping;
    const MPI_Comm                           comm;
    dealii::IndexSet                         owned, relevant;
    /// Every boundary DoF (and hanging ones) constrained to zero.
    dealii::AffineConstraints<double>      boundary_constraints;
    dealii::TrilinosWrappers::SparseMatrix matrix;
    LinearSolver                           solver{LinearSolver::Parameters()};
    bool                                   ready = false;
  };
} // namespace forma

#endif
