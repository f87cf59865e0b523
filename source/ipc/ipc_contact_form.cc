#include <forma/adjoint/physical_parameters.h>
#include <forma/adjoint/shape_field.h>
#include <forma/ipc/ipc_contact_form.h>

namespace forma
{
  namespace ipc
  {
    using namespace dealii;

    template <int dim>
    IpcContactForm<dim>::IpcContactForm(
      IpcContact<dim>               &contact,
      const std::function<double()> &friction_eta)
      : contact(contact)
      , friction_eta(friction_eta)
    {}



    template <int dim>
    void
    IpcContactForm<dim>::add_couplings(
      const typename Form<dim>::Constraints &constraints,
      TrilinosWrappers::SparsityPattern     &pattern) const
    {
      contact.add_couplings(constraints, pattern);
    }



    template <int dim>
    void
    IpcContactForm<dim>::assemble_global(GlobalAssembly &a) const
    {
      // Collective: every rank, whatever the cells said.
      bool apart = true;
      a.energy += contact.assemble(
        a.u_owned, a.constraints, a.matrix, a.residual, a.raw, apart, !a.exact);
      a.admissible &= apart;
    }



    template <int dim>
    bool
    IpcContactForm<dim>::update_state(const Vector &u, const Vector *du)
    {
      return contact.update_candidates(u, du);
    }



    template <int dim>
    double
    IpcContactForm<dim>::max_step(const Vector &u,
                                  const Vector &du,
                                  const double  gap)
    {
      return contact.max_step(u, du, gap);
    }



    template <int dim>
    bool
    IpcContactForm<dim>::prepare_adjoint_step(const Vector &u,
                                              const Vector *u_lagged)
    {
      // Friction lagged as in the forward step (at rest for static runs),
      // candidates at the stored state.
      if (contact.has_friction())
        {
          Vector lagged(u);
          if (u_lagged)
            lagged = *u_lagged;
          else
            lagged = 0;
          contact.update_friction(lagged, lagged, friction_eta());
        }
      return contact.update_candidates(u, nullptr);
    }



    template <int dim>
    void
    IpcContactForm<dim>::global_products(const GlobalAdjoint &a,
                                         PhysicalParameters  &parameters) const
    {
      typename IpcContact<dim>::AdjointProducts out;
      contact.adjoint_products(
        a.u_owned, a.p_owned, a.constraints, a.lagged, out);
      if (auto *friction = parameters.wanted<FrictionCoefficients>())
        for (unsigned int k = 0; k < out.friction.size(); ++k)
          friction->sensitivity[k] += out.friction[k];
      if (auto *shape = parameters.wanted<ShapeField<dim>>())
        add_rest_gradient(out.rest, *shape);
    }



    template <int dim>
    void
    IpcContactForm<dim>::add_rest_gradient(const std::vector<Vec> &rest,
                                           ShapeField<dim>        &shape) const
    {
      const auto                          &m = contact.mesh();
      std::vector<types::global_dof_index> dofs;
      std::vector<double>                  values;
      for (unsigned int v = 0; v < m.n_vertices(); ++v)
        if (!m.fixed(v) && rest[v].norm_square() > 0)
          for (const auto &w : m.shape_weights[v])
            {
              dofs.push_back(w.dof);
              values.push_back(w.weight * rest[v][w.component]);
            }
      shape.add(dealii::Vector<double>(values.begin(), values.end()), dofs);
      shape.sensitivity.compress(VectorOperation::add);
    }

    template class IpcContactForm<2>;
    template class IpcContactForm<3>;
  } // namespace ipc
} // namespace forma
