#include <deal.II/lac/vector.h>

#include <forma/physics/surface_load_form.h>

namespace forma
{
  using namespace dealii;

  template <int dim>
  SurfaceLoadForm<dim>::SurfaceLoadForm(const std::vector<Load> &tractions,
                                        const std::vector<Load> &pressures,
                                        const LoadScales        &scales)
    : tractions(tractions)
    , pressures(pressures)
    , scales(scales)
  {}



  template <int dim>
  void
  SurfaceLoadForm<dim>::set_time(const double t)
  {
    for (const auto &l : tractions)
      l.second->set_time(t);
    for (const auto &l : pressures)
      l.second->set_time(t);
  }



  template <int dim>
  bool
  SurfaceLoadForm<dim>::acts_on_boundary(const types::boundary_id id) const
  {
    for (const auto &l : tractions)
      if (l.first == id)
        return true;
    for (const auto &l : pressures)
      if (l.first == id)
        return true;
    return false;
  }



  template <int dim>
  void
  SurfaceLoadForm<dim>::face_terms(const PointStates<dim> &s,
                                   PointTerms<dim>        &t) const
  {
    const types::boundary_id           id = s.cell.boundary_id;
    static thread_local Vector<double> val(dim); // per quadrature point
    for (unsigned int q = 0; q < s.size(); ++q)
      {
        Tensor<1, dim> load;
        for (unsigned int k = 0; k < tractions.size(); ++k)
          if (tractions[k].first == id)
            {
              tractions[k].second->vector_value(s.X[q], val);
              for (unsigned int d = 0; d < dim; ++d)
                load[d] += scales.value[k] * val[d];
            }
        for (unsigned int k = 0; k < pressures.size(); ++k)
          if (pressures[k].first == id)
            load -= scales.value[tractions.size() + k] *
                    pressures[k].second->value(s.X[q], 0) * s.normal[q];
        t.source[q] -= load;
        if (t.with_energy)
          t.energy -= (load * s.u[q]) * s.JxW[q];
      }
  }



  template <int dim>
  void
  SurfaceLoadForm<dim>::face_products(const PointStates<dim>      &s,
                                      const PointAdjoint<dim>     &a,
                                      std::vector<Tensor<2, dim>> &shape_kernel,
                                      PhysicalParameters &parameters) const
  {
    const types::boundary_id id          = s.cell.boundary_id;
    auto                    *sensitivity = parameters.wanted<LoadScales>();
    static thread_local Vector<double> val(dim);
    for (unsigned int q = 0; q < s.size(); ++q)
      {
        const double          JxW = s.JxW[q];
        const Tensor<1, dim> &n   = s.normal[q];
        const Tensor<1, dim> &p   = a.p[q];
        Tensor<1, dim>        traction;
        double                pressure = 0;
        for (unsigned int k = 0; k < tractions.size(); ++k)
          if (tractions[k].first == id)
            {
              tractions[k].second->vector_value(s.X[q], val);
              double tp = 0;
              for (unsigned int d = 0; d < dim; ++d)
                {
                  traction[d] += scales.value[k] * val[d];
                  tp += val[d] * p[d];
                }
              if (sensitivity)
                sensitivity->sensitivity[k] -= tp * JxW;
            }
        for (unsigned int k = 0; k < pressures.size(); ++k)
          if (pressures[k].first == id)
            {
              const double       pk = pressures[k].second->value(s.X[q]);
              const unsigned int m  = tractions.size() + k;
              pressure += scales.value[m] * pk;
              if (sensitivity)
                sensitivity->sensitivity[m] += pk * (n * p) * JxW;
            }
        // -int t.p ds and int P n.p ds on the moving surface, as
        // W : grad theta with W_cl = -t.p (delta_cl - n_c n_l)
        //                           + P (n.p delta_cl - n_c p_l).
        const double   tp = traction * p, np = n * p;
        Tensor<2, dim> W;
        for (unsigned int c = 0; c < dim; ++c)
          for (unsigned int l = 0; l < dim; ++l)
            W[c][l] = -tp * ((c == l ? 1. : 0.) - n[c] * n[l]) +
                      pressure * ((c == l ? np : 0.) - n[c] * p[l]);
        shape_kernel[q] += W * JxW;
      }
  }

  template class SurfaceLoadForm<2>;
  template class SurfaceLoadForm<3>;
} // namespace forma
