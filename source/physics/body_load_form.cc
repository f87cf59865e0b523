#include <deal.II/lac/vector.h>

#include <forma/physics/body_load_form.h>

namespace forma
{
  using namespace dealii;

  template <int dim>
  BodyLoadForm<dim>::BodyLoadForm(
    const std::shared_ptr<Function<dim>>       &body_force,
    const Tensor<1, dim>                       &gravity,
    const std::map<types::material_id, double> &density,
    const LoadScales                           &scales,
    const unsigned int                          first)
    : body_force(body_force)
    , gravity(gravity)
    , density(density)
    , scales(scales)
    , body_index(first)
    , gravity_index(first + (body_force ? 1 : 0))
  {}



  template <int dim>
  void
  BodyLoadForm<dim>::set_time(const double t)
  {
    if (body_force)
      body_force->set_time(t);
  }



  template <int dim>
  Tensor<1, dim>
  BodyLoadForm<dim>::body_force_at(const Point<dim> &X) const
  {
    Tensor<1, dim> f;
    if (!body_force)
      return f;
    // Per-thread buffer: this runs at every quadrature point.
    static thread_local Vector<double> b(dim);
    body_force->vector_value(X, b);
    for (unsigned int d = 0; d < dim; ++d)
      f[d] = b[d];
    return f;
  }



  template <int dim>
  void
  BodyLoadForm<dim>::cell_terms(const PointStates<dim> &s,
                                PointTerms<dim>        &t) const
  {
    const double rho         = density.at(s.cell.material_id);
    const bool   has_gravity = gravity.norm() > 0;
    const double s_g         = has_gravity ? scales.value[gravity_index] : 0.;
    const double s_b         = body_force ? scales.value[body_index] : 0.;
    for (unsigned int q = 0; q < s.size(); ++q)
      {
        Tensor<1, dim> f = -s_g * rho * gravity;
        if (body_force)
          f -= s_b * body_force_at(s.X[q]);
        t.source[q] += f;
        if (t.with_energy)
          t.energy += (f * s.u[q]) * s.JxW[q];
      }
  }



  template <int dim>
  void
  BodyLoadForm<dim>::cell_products(const PointStates<dim>  &s,
                                   const PointAdjoint<dim> &a,
                                   PhysicalParameters      &parameters) const
  {
    auto *sensitivity = parameters.wanted<LoadScales>();
    if (!sensitivity)
      return;
    const double rho = density.at(s.cell.material_id);
    for (unsigned int q = 0; q < s.size(); ++q)
      {
        // d/ds of -int s b . p.
        if (body_force)
          sensitivity->sensitivity[body_index] -=
            (body_force_at(s.X[q]) * a.p[q]) * s.JxW[q];
        if (gravity.norm() > 0)
          sensitivity->sensitivity[gravity_index] -=
            rho * (gravity * a.p[q]) * s.JxW[q];
      }
  }

  template class BodyLoadForm<2>;
  template class BodyLoadForm<3>;
} // namespace forma
