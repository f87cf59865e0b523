#ifndef forma_adjoint_shape_field_h
#define forma_adjoint_shape_field_h

#include <deal.II/base/types.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

#include <forma/adjoint/physical_parameters.h>

#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class DoFHandler;
}

namespace forma
{
  /**
   * The shape as a physical parameter (thesis ch. 3.7.1): the offset of the
   * shape field's DoFs (a vector Q1/P1 field of positions) from the mesh's
   * vertices, before its constraints (fixed vertices, symmetry planes,
   * hanging vertices) apply, and the sensitivity dJ/d(offset), condensed
   * with those constraints.
   */
  template <int dim>
  class ShapeField : public PhysicalParameter
  {
  public:
    using Vector = dealii::TrilinosWrappers::MPI::Vector;

    ShapeField(const dealii::DoFHandler<dim, dim>      &dof_handler,
               const dealii::AffineConstraints<double> &constraints)
      : dof_handler(dof_handler)
      , constraints(constraints)
    {}

    void
    clear_sensitivity() override
    {
      sensitivity = 0;
    }

    /// Add p^T dh/dx of local shape DoFs `dofs` to the sensitivity (not
    /// compressed: the caller compresses once with VectorOperation::add).
    void
    add(const dealii::Vector<double>                       &local,
        const std::vector<dealii::types::global_dof_index> &dofs)
    {
      constraints.distribute_local_to_global(local, dofs, sensitivity);
    }

    const dealii::DoFHandler<dim, dim>      &dof_handler;
    const dealii::AffineConstraints<double> &constraints;
    Vector                                   offset;      ///< owned
    Vector                                   sensitivity; ///< owned
  };
} // namespace forma

#endif
