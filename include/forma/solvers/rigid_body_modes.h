#ifndef forma_solvers_rigid_body_modes_h
#define forma_solvers_rigid_body_modes_h

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/hp/mapping_collection.h>

#include <vector>

namespace forma
{
  /**
   * The near null space of elasticity on a vector-valued DoFHandler with
   * `dim` components, for algebraic multigrid: owned entries of the `dim`
   * translations and the rotations (2D: one; 3D: about z, x, y), evaluated
   * at the support points of the DoFs under `mapping`.
   */
  struct RigidBodyModes
  {
    std::vector<std::vector<double>> modes;
    /// `dim` when the owned DoFs come in node-wise groups of all components
    /// (x, y[, z] of one support point in a row, as FESystem numbers them up
    /// to degree 2): ML then aggregates nodes instead of scalar unknowns,
    /// which halves the iterations on 3D elasticity. 1 otherwise.
    unsigned int pde_equations = 1;
  };

  template <int dim>
  RigidBodyModes
  rigid_body_modes(const dealii::hp::MappingCollection<dim> &mapping,
                   const dealii::DoFHandler<dim>            &dof_handler);
} // namespace forma

#endif
