#include <forma/physics/contractions.h>
#include <forma/physics/damping_form.h>

namespace forma
{
  using namespace dealii;

  template <int dim>
  DampingForm<dim>::DampingForm(const CellDamping &coefficients)
    : coefficients(coefficients)
  {}



  template <int dim>
  Damping<dim>
  DampingForm<dim>::damping(const CellInfo &cell) const
  {
    const auto &d = coefficients.value[cell.active_index];
    return Damping<dim>(d[0], d[1]);
  }



  template <int dim>
  void
  DampingForm<dim>::cell_terms(const PointStates<dim> &s,
                               PointTerms<dim>        &t) const
  {
    const Damping<dim> damp = damping(s.cell);
    if (!damp.active())
      return;
    for (unsigned int q = 0; q < s.size(); ++q)
      {
        const Tensor<2, dim> &g = s.grad_u[q], &g_old = s.grad_u_old[q];
        t.flux[q] += damp.stress(g, g_old, s.dt);
        if (t.with_tangent)
          t.flux_tangent[q] += damp.tangent(g, g_old, s.dt);
        if (t.with_old_tangent)
          t.flux_tangent_old[q] += damp.tangent_old(g, g_old, s.dt);
        if (t.with_energy)
          t.energy += damp.dissipation_potential(g, g_old, s.dt) * s.JxW[q];
      }
  }



  template <int dim>
  void
  DampingForm<dim>::cell_products(const PointStates<dim>  &s,
                                  const PointAdjoint<dim> &a,
                                  PhysicalParameters      &parameters) const
  {
    auto *sensitivity = parameters.wanted<CellDamping>();
    if (!sensitivity)
      return;
    // The stress is linear in the coefficients.
    const Damping<dim> unit_shear(1., 0.), unit_bulk(0., 1.);
    auto              &d = sensitivity->sensitivity[s.cell.active_index];
    for (unsigned int q = 0; q < s.size(); ++q)
      {
        const Tensor<2, dim> &g = s.grad_u[q], &g_old = s.grad_u_old[q];
        d[0] +=
          scalar_product(unit_shear.stress(g, g_old, s.dt), a.G[q]) * s.JxW[q];
        d[1] +=
          scalar_product(unit_bulk.stress(g, g_old, s.dt), a.G[q]) * s.JxW[q];
      }
  }



  template <int dim>
  void
  DampingForm<dim>::history_terms(const HistoryStates<dim> &s,
                                  PointTerms<dim>          &t) const
  {
    const Damping<dim> damp = damping(s.cell);
    if (s.G_next.empty() || !damp.active())
      return;
    for (unsigned int q = 0; q < s.JxW.size(); ++q)
      t.flux[q] += contract_left(s.G_next[q],
                                 damp.tangent_old(s.grad_u_next[q],
                                                  s.grad_u_prev[q],
                                                  s.dt));
  }

  template class DampingForm<2>;
  template class DampingForm<3>;
} // namespace forma
