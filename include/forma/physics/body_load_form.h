#ifndef forma_physics_body_load_form_h
#define forma_physics_body_load_form_h

#include <deal.II/base/function.h>
#include <deal.II/base/types.h>

#include <forma/adjoint/form.h>
#include <forma/adjoint/physical_parameters.h>

#include <map>
#include <memory>

namespace forma
{
  /**
   * Dead volume loads: -int (s_g rho g + s_b b(X)) . v with gravity g, a body
   * force density b of the material coordinates X, and their scales s_g, s_b
   * from LoadScales (entries `first` and on: body force, then gravity, where
   * present). Energy: the load's potential. Products: d/d(scales).
   */
  template <int dim>
  class BodyLoadForm : public Form<dim>
  {
  public:
    /// `body_force` may be null, `gravity` zero; density by material id.
    BodyLoadForm(const std::shared_ptr<dealii::Function<dim>>       &body_force,
                 const dealii::Tensor<1, dim>                       &gravity,
                 const std::map<dealii::types::material_id, double> &density,
                 const LoadScales                                   &scales,
                 const unsigned int                                  first);

    std::string
    name() const override
    {
      return "body load";
    }

    unsigned int
    needs() const override
    {
      return Form<dim>::values;
    }

    void
    set_time(const double t) override;

    bool
    has_cell_terms() const override
    {
      return true;
    }

    void
    cell_terms(const PointStates<dim> &s, PointTerms<dim> &t) const override;

    void
    cell_products(const PointStates<dim>  &s,
                  const PointAdjoint<dim> &a,
                  PhysicalParameters      &parameters) const override;

  private:
    /// b(X) (zero without a body force).
    dealii::Tensor<1, dim>
    body_force_at(const dealii::Point<dim> &X) const;

    const std::shared_ptr<dealii::Function<dim>>       body_force;
    const dealii::Tensor<1, dim>                       gravity;
    const std::map<dealii::types::material_id, double> density;
    const LoadScales                                  &scales;
    const unsigned int body_index, gravity_index; ///< in scales
  };
} // namespace forma

#endif
