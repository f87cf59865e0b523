#include <forma/physics/inertia_form.h>

namespace forma
{
  using namespace dealii;

  template <int dim>
  InertiaForm<dim>::InertiaForm(
    const std::map<types::material_id, double> &density)
    : density(density)
  {}



  template <int dim>
  void
  InertiaForm<dim>::cell_terms(const PointStates<dim> &s,
                               PointTerms<dim>        &t) const
  {
    const double m = density.at(s.cell.material_id) * s.inertia_factor;
    for (unsigned int q = 0; q < s.size(); ++q)
      {
        const Tensor<1, dim> a = s.u[q] + s.w[q];
        t.source[q] += m * a;
        if (t.with_tangent)
          t.source_tangent[q] += m;
        if (t.with_energy)
          t.energy += 0.5 * m * (a * a) * s.JxW[q];
      }
  }



  template <int dim>
  void
  InertiaForm<dim>::history_terms(const HistoryStates<dim> &s,
                                  PointTerms<dim>          &t) const
  {
    const double rho = density.at(s.cell.material_id);
    for (unsigned int q = 0; q < s.JxW.size(); ++q)
      t.source[q] += rho * s.z[q];
  }

  template class InertiaForm<2>;
  template class InertiaForm<3>;
} // namespace forma
