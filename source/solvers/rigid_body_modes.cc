#include <deal.II/dofs/dof_tools.h>

#include <forma/solvers/rigid_body_modes.h>

#include <map>

namespace forma
{
  using namespace dealii;

  namespace
  {
    // Components of the owned DoFs, in the order of the owned index set.
    template <int dim>
    std::vector<unsigned int>
    owned_components(const DoFHandler<dim> &dof_handler)
    {
      const IndexSet           &owned = dof_handler.locally_owned_dofs();
      std::vector<unsigned int> component(owned.n_elements());
      std::vector<types::global_dof_index> dofs;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            dofs.resize(cell->get_fe().n_dofs_per_cell());
            cell->get_dof_indices(dofs);
            for (unsigned int i = 0; i < dofs.size(); ++i)
              if (owned.is_element(dofs[i]))
                component[owned.index_within_set(dofs[i])] =
                  cell->get_fe().system_to_component_index(i).first;
          }
      return component;
    }
  } // namespace



  template <int dim>
  RigidBodyModes
  rigid_body_modes(const hp::MappingCollection<dim> &mapping,
                   const DoFHandler<dim>            &dof_handler)
  {
    std::map<types::global_dof_index, Point<dim>> support;
    DoFTools::map_dofs_to_support_points(mapping, dof_handler, support);
    const IndexSet                 &owned = dof_handler.locally_owned_dofs();
    const std::vector<unsigned int> component = owned_components(dof_handler);
    const unsigned int              n_rot     = dim == 2 ? 1 : 3;
    RigidBodyModes                  result;
    result.modes.assign(dim + n_rot, std::vector<double>(owned.n_elements()));
    bool blocked = owned.n_elements() % dim == 0;
    for (const auto i : owned)
      {
        const unsigned int k = owned.index_within_set(i);
        const unsigned int c = component[k];
        const Point<dim>   x = support.at(i);
        blocked &= (c == k % dim);
        result.modes[c][k] = 1.;
        if (dim == 2)
          result.modes[2][k] = (c == 0 ? -x[1] : x[0]);
        else
          {
            // rotations about z, x, y
            const double r_z[3]      = {-x[1], x[0], 0};
            const double r_x[3]      = {0, -x[dim - 1], x[1]};
            const double r_y[3]      = {x[dim - 1], 0, -x[0]};
            result.modes[dim][k]     = r_z[c];
            result.modes[dim + 1][k] = r_x[c];
            result.modes[dim + 2][k] = r_y[c];
          }
      }
    // ML needs the same grouping on every rank.
    const bool all_blocked =
      Utilities::MPI::min(blocked ? 1u : 0u, dof_handler.get_communicator()) ==
      1u;
    result.pde_equations = all_blocked ? dim : 1;
    return result;
  }



  template RigidBodyModes
  rigid_body_modes(const hp::MappingCollection<2> &, const DoFHandler<2> &);
  template RigidBodyModes
  rigid_body_modes(const hp::MappingCollection<3> &, const DoFHandler<3> &);
} // namespace forma
