#ifndef forma_physics_elastic_form_h
#define forma_physics_elastic_form_h

#include <forma/adjoint/form.h>
#include <forma/adjoint/physical_parameters.h>
#include <forma/physics/material.h>

#include <map>

namespace forma
{
  /**
   * The internal force int P(grad u) : grad v of linear or Neo-Hookean bodies
   * (thesis ch. 3.7.2), with the Lame pair of each cell from CellLame and the
   * other properties (density) of its body. Its energy is the stored energy
   * int W(grad u). Products: d/d(lambda, mu) per cell.
   */
  template <int dim>
  class ElasticForm : public Form<dim>
  {
  public:
    /// `inversion_free`: states with det F <= 0 are inadmissible for every
    /// model (IPC contact needs it).
    ElasticForm(
      const ConstitutiveModel model,
      const bool              plane_stress,
      const std::map<dealii::types::material_id, MaterialProperties> &bodies,
      const CellLame                                                 &lame,
      const bool inversion_free);

    std::string
    name() const override
    {
      return "elastic";
    }

    bool
    has_cell_terms() const override
    {
      return true;
    }

    /// The material law of a cell.
    Material<dim>
    material(const CellInfo &cell) const;

    void
    cell_terms(const PointStates<dim> &s, PointTerms<dim> &t) const override;

    void
    cell_products(const PointStates<dim>  &s,
                  const PointAdjoint<dim> &a,
                  PhysicalParameters      &parameters) const override;

  private:
    const ConstitutiveModel                                        model;
    const bool                                                     plane_stress;
    const std::map<dealii::types::material_id, MaterialProperties> bodies;
    const CellLame                                                &lame;
    const bool inversion_free;
  };
} // namespace forma

#endif
