#ifndef forma_homogenization_base_material_h
#define forma_homogenization_base_material_h

#include <deal.II/base/symmetric_tensor.h>

#include <forma/homogenization/elastic_tensor.h>

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <utility>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace forma
{
  /**
   * The printable base material of a microstructure family: the `Base
   * material` section every homogenization app shares (an app adds its own
   * entries to the section after declare()). Young's modulus and Poisson's
   * ratio are the 3D material's; `moduli()` are the 2D ones of the plane
   * model, which the homogenized results are relative to.
   */
  struct BaseMaterial
  {
    double     young   = 1;
    double     poisson = 0;
    PlaneModel plane   = PlaneModel::plane_stress;
    /// Other base Poisson's ratios the results are also given for, by the
    /// CLM transform (thesis eq. 4.11).
    std::vector<double> clm_poisson;

    /// Declares the section and its shared entries.
    static void
    declare(dealii::ParameterHandler &prm);

    /// Reads them; a non-positive modulus is an error naming the entry.
    static BaseMaterial
    parse(dealii::ParameterHandler &prm);

    /// The 2D moduli of the plane model.
    IsotropicModuli
    moduli() const;

    /// For each of `clm_poisson`: that base Poisson's ratio and the
    /// isotropic fit of `C` (homogenized with this base) made of it.
    std::vector<std::pair<double, IsotropicModuli>>
    clm_fits(const dealii::SymmetricTensor<4, 2> &C) const;

    /// E, nu, plane model and the 2D E, nu (summary.json's base_material).
    nlohmann::json
    summary() const;
  };
} // namespace forma

#endif
