#ifndef forma_physics_damping_form_h
#define forma_physics_damping_form_h

#include <forma/adjoint/form.h>
#include <forma/adjoint/physical_parameters.h>
#include <forma/physics/damping.h>

namespace forma
{
  /**
   * Strain-rate damping int P_d(grad u^i, grad u^{i-1}) : grad v of transient
   * problems (Damping, thesis ch. 3.7.2), with the coefficients of each cell
   * from CellDamping. Its energy is the dissipation potential; it couples
   * step i to step i - 1 (history_terms()). Products: d/d(shear, bulk).
   */
  template <int dim>
  class DampingForm : public Form<dim>
  {
  public:
    explicit DampingForm(const CellDamping &coefficients);

    std::string
    name() const override
    {
      return "damping";
    }

    bool
    transient_only() const override
    {
      return true;
    }

    unsigned int
    needs() const override
    {
      return Form<dim>::old_gradients;
    }

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

    void
    history_terms(const HistoryStates<dim> &s,
                  PointTerms<dim>          &t) const override;

  private:
    Damping<dim>
    damping(const CellInfo &cell) const;

    const CellDamping &coefficients;
  };
} // namespace forma

#endif
