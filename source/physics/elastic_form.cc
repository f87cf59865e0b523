#include <deal.II/base/symmetric_tensor.h>

#include <forma/physics/elastic_form.h>

namespace forma
{
  using namespace dealii;

  template <int dim>
  ElasticForm<dim>::ElasticForm(
    const ConstitutiveModel                                 model,
    const bool                                              plane_stress,
    const std::map<types::material_id, MaterialProperties> &bodies,
    const CellLame                                         &lame,
    const bool                                              inversion_free)
    : model(model)
    , plane_stress(plane_stress)
    , bodies(bodies)
    , lame(lame)
    , inversion_free(inversion_free)
  {}



  template <int dim>
  Material<dim>
  ElasticForm<dim>::material(const CellInfo &cell) const
  {
    MaterialProperties m = bodies.at(cell.material_id);
    const auto        &l = lame.value[cell.active_index];
    m.lambda             = l[0];
    m.mu                 = l[1];
    return Material<dim>(model, m, plane_stress);
  }



  template <int dim>
  void
  ElasticForm<dim>::cell_terms(const PointStates<dim> &s,
                               PointTerms<dim>        &t) const
  {
    const Material<dim> mat = material(s.cell);
    for (unsigned int q = 0; q < s.size(); ++q)
      {
        const Tensor<2, dim> &grad_u = s.grad_u[q];
        if (!mat.admissible(grad_u) ||
            (inversion_free &&
             determinant(unit_symmetric_tensor<dim>() + grad_u) <= 0))
          {
            t.admissible = false;
            return;
          }
        t.flux[q] += mat.stress(grad_u);
        if (t.with_tangent)
          t.flux_tangent[q] += mat.tangent(grad_u);
        if (t.with_energy)
          t.energy += mat.energy_density(grad_u) * s.JxW[q];
      }
  }



  template <int dim>
  void
  ElasticForm<dim>::cell_products(const PointStates<dim>  &s,
                                  const PointAdjoint<dim> &a,
                                  PhysicalParameters      &parameters) const
  {
    auto *sensitivity = parameters.wanted<CellLame>();
    if (!sensitivity)
      return;
    const Material<dim> mat = material(s.cell);
    auto               &l   = sensitivity->sensitivity[s.cell.active_index];
    for (unsigned int q = 0; q < s.size(); ++q)
      {
        const auto dP = mat.stress_lame_derivatives(s.grad_u[q]);
        l[0] += scalar_product(dP[0], a.G[q]) * s.JxW[q];
        l[1] += scalar_product(dP[1], a.G[q]) * s.JxW[q];
      }
  }

  template class ElasticForm<2>;
  template class ElasticForm<3>;
} // namespace forma
