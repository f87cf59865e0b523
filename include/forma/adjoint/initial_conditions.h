#ifndef forma_adjoint_initial_conditions_h
#define forma_adjoint_initial_conditions_h

#include <deal.II/base/types.h>
#include <deal.II/lac/trilinos_vector.h>

#include <forma/adjoint/physical_parameters.h>

#include <vector>

namespace forma
{
  /**
   * Offsets added to the initial displacement and velocity of a transient
   * problem (thesis ch. 3.5.3), as displacement-space vectors, and the
   * sensitivities dJ/du^0, dJ/dv^0 the transient adjoint computes. For the
   * parameterizations: the component and the body (material id of the
   * first cell that has it) of every locally owned DoF.
   */
  class InitialConditions : public PhysicalParameter
  {
  public:
    using Vector = dealii::TrilinosWrappers::MPI::Vector;

    void
    clear_sensitivity() override
    {
      displacement_sensitivity = 0;
      velocity_sensitivity     = 0;
    }

    Vector displacement, velocity; ///< owned offsets (zero: none)
    Vector displacement_sensitivity, velocity_sensitivity;
    std::vector<unsigned int>               component; ///< per owned DoF
    std::vector<dealii::types::material_id> body;      ///< per owned DoF
  };
} // namespace forma

#endif
