#ifndef forma_adjoint_shape_filter_h
#define forma_adjoint_shape_filter_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/types.h>

#include <functional>
#include <utility>
#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class DoFHandler;
}

namespace forma
{
  /**
   * A kernel filter of shape designs (vertex morphing, Hojjat et al. 2014):
   * the offset of a vertex is the weighted mean of the design entries of
   * the vertices within `radius` of it on the mesh as read, with the hat
   * weight 1 - d / radius, over the vertices that share a material with it
   * (parts do not pull each other along); fixed vertices count with a zero
   * entry, so moves fade out towards them. The optimizer then works on a
   * control field whose gradient is the filtered sensitivity: no kinks
   * below the radius, steps that do not depend on the mesh size, and the
   * same minimizers within the filtered shapes.
   *
   * Entries of a vector Q1/P1 shape field's DoFs; every rank holds the
   * whole design vector, rows are built for the locally owned DoFs.
   */
  template <int dim>
  class ShapeFilter
  {
  public:
    /// `filtered(i)` says whether shape DoF i (locally owned) takes part;
    /// the others keep their own entry. `fixed(i)`: a DoF that does not
    /// move, which counts as a zero entry in its neighbours' means.
    ShapeFilter(
      const dealii::DoFHandler<dim, dim>                         &dof_handler,
      const double                                                radius,
      const std::function<bool(dealii::types::global_dof_index)> &filtered,
      const std::function<bool(dealii::types::global_dof_index)> &fixed,
      const MPI_Comm                                              comm);

    /// (A q)_i for a locally owned DoF i.
    double
    value(const double *q, const dealii::types::global_dof_index i) const;

    /// dJ_j += A_ij g for every j (the transpose, row i's part).
    void
    add_transpose(const dealii::types::global_dof_index i,
                  const double                          g,
                  double                               *dJ) const;

  private:
    using Row = std::vector<std::pair<dealii::types::global_dof_index, double>>;
    /// By global DoF index; empty rows are the identity.
    std::vector<Row> rows;
  };
} // namespace forma

#endif
