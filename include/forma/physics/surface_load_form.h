#ifndef forma_physics_surface_load_form_h
#define forma_physics_surface_load_form_h

#include <deal.II/base/function.h>
#include <deal.II/base/types.h>

#include <forma/adjoint/form.h>
#include <forma/adjoint/physical_parameters.h>

#include <memory>
#include <utility>
#include <vector>

namespace forma
{
  /**
   * Surface loads on boundary ids: -int_Gamma (sum_k s_k t_k(X) - sum_k s_k
   * p_k(X) n) . v with tractions t_k and pressures p_k on the current
   * shape's outer normal n (dead loads in u), scaled by LoadScales entries
   * 0.. (tractions, then pressures, in record order). Energy: the loads'
   * potential. Products: d/d(scales) and the shape kernel of the moving
   * surface (d ds = div_S theta ds, d(n ds) = (div theta n - grad theta^T n)
   * ds).
   */
  template <int dim>
  class SurfaceLoadForm : public Form<dim>
  {
  public:
    using Load = std::pair<dealii::types::boundary_id,
                           std::shared_ptr<dealii::Function<dim>>>;

    SurfaceLoadForm(const std::vector<Load> &tractions,
                    const std::vector<Load> &pressures,
                    const LoadScales        &scales);

    std::string
    name() const override
    {
      return "surface load";
    }

    unsigned int
    needs() const override
    {
      return Form<dim>::values;
    }

    void
    set_time(const double t) override;

    bool
    acts_on_boundary(const dealii::types::boundary_id id) const override;

    void
    face_terms(const PointStates<dim> &s, PointTerms<dim> &t) const override;

    void
    face_products(const PointStates<dim>              &s,
                  const PointAdjoint<dim>             &a,
                  std::vector<dealii::Tensor<2, dim>> &shape_kernel,
                  PhysicalParameters &parameters) const override;

  private:
    const std::vector<Load> tractions, pressures;
    const LoadScales       &scales;
  };
} // namespace forma

#endif
