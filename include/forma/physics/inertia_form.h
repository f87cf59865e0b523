#ifndef forma_physics_inertia_form_h
#define forma_physics_inertia_form_h

#include <deal.II/base/types.h>

#include <forma/adjoint/form.h>

#include <map>

namespace forma
{
  /**
   * Inertia of a BDF step (thesis eq. 3.12 solved for u^i):
   *   int rho (u + w) . v / (beta dt)^2
   * with w the BDF history of earlier displacements and velocities. Its
   * energy is rho |u + w|^2 / (2 (beta dt)^2) (the incremental potential);
   * its history terms are the mass matrix times the BDF-weighted adjoints.
   */
  template <int dim>
  class InertiaForm : public Form<dim>
  {
  public:
    /// Density by material id.
    explicit InertiaForm(
      const std::map<dealii::types::material_id, double> &density);

    std::string
    name() const override
    {
      return "inertia";
    }

    bool
    transient_only() const override
    {
      return true;
    }

    unsigned int
    needs() const override
    {
      return Form<dim>::values | Form<dim>::history;
    }

    bool
    has_cell_terms() const override
    {
      return true;
    }

    void
    cell_terms(const PointStates<dim> &s, PointTerms<dim> &t) const override;

    void
    history_terms(const HistoryStates<dim> &s,
                  PointTerms<dim>          &t) const override;

  private:
    const std::map<dealii::types::material_id, double> density;
  };
} // namespace forma

#endif
