#include <deal.II/base/exceptions.h>
#include <deal.II/base/parameter_handler.h>

#include <forma/base/records.h>
#include <forma/homogenization/base_material.h>
#include <forma/homogenization/bounds.h>

#include <nlohmann/json.hpp>

namespace forma
{
  using namespace dealii;

  void
  BaseMaterial::declare(ParameterHandler &prm)
  {
    prm.enter_subsection("Base material");
    prm.declare_entry("Young's modulus",
                      "1",
                      Patterns::Double(0),
                      "E of the printable base material; results scale with "
                      "it.");
    prm.declare_entry("Poisson's ratio",
                      "0",
                      Patterns::Double(-1, 0.5),
                      "nu of the base material (3D); the thesis uses 0.");
    prm.declare_entry("Plane model",
                      "plane stress",
                      Patterns::Selection("plane stress|plane strain"),
                      "2D model of the base material; results are 2D moduli "
                      "(see the app's page in doc/).");
    prm.declare_entry(
      "CLM Poisson's ratios",
      "",
      Patterns::Anything(),
      "Comma separated base Poisson's ratios for which the results are also "
      "given by the CLM transform (eq. 4.11), without recomputing.");
    prm.leave_subsection();
  }



  BaseMaterial
  BaseMaterial::parse(ParameterHandler &prm)
  {
    BaseMaterial b;
    prm.enter_subsection("Base material");
    b.young       = prm.get_double("Young's modulus");
    b.poisson     = prm.get_double("Poisson's ratio");
    b.plane       = plane_model_from_string(prm.get("Plane model"));
    b.clm_poisson = parse_numbers(prm.get("CLM Poisson's ratios"),
                                  "Base material/CLM Poisson's ratios",
                                  -1,
                                  0.5);
    prm.leave_subsection();
    AssertThrow(b.young > 0,
                ExcMessage("Base material/Young's modulus must be positive"));
    return b;
  }



  IsotropicModuli
  BaseMaterial::moduli() const
  {
    return IsotropicModuli::of_material(young, poisson, plane);
  }



  std::vector<std::pair<double, IsotropicModuli>>
  BaseMaterial::clm_fits(const SymmetricTensor<4, 2> &C) const
  {
    std::vector<std::pair<double, IsotropicModuli>> fits;
    for (const double nu : clm_poisson)
      fits.emplace_back(
        nu,
        isotropic_fit(clm_transform(
          C, moduli(), IsotropicModuli::of_material(young, nu, plane))));
    return fits;
  }



  nlohmann::json
  BaseMaterial::summary() const
  {
    const IsotropicModuli m = moduli();
    return {{"E", young},
            {"nu", poisson},
            {"plane_model",
             plane == PlaneModel::plane_stress ? "plane stress" :
                                                 "plane strain"},
            {"E_2d", m.E},
            {"nu_2d", m.nu}};
  }
} // namespace forma
