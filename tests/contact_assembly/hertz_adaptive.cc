// Contact-aware refinement on the shipped Hertz example (a thick ring
// squeezed between rigid planes, by its quarter; Contact/Rigid gaps puts
// the plane at distance 1 - x). The coarse mesh's quadrature points miss
// the plane: Kelly alone sees a rigid translation and never refines
// towards the contact, while Kelly plus the contact faces' traction
// residual finds the contact and resolves it: peak pressure and half-width
// as Hertz's for the computed force (plane strain, rigid flat):
//   a = sqrt(4 P R / (pi E*)), p0 = sqrt(P E* / (pi R)), E* = E / (1 - nu^2).
// The gradient of a stress norm in the cells' Lame parameters passes its
// Taylor test on the adapted mesh.

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <cmath>

int
main()
{
  initlog();
  const double e_star = 1. / (1. - 0.09), R = 1.;

  const auto  s      = run_example("contact_assembly",
                             "hertz_ring",
                             " --set 'Finite element/Adaptive cycles=7'");
  const auto &cycles = s["cycles"];
  check("8 cycles", cycles.size() == 8);
  check("cycle 0 (coarse mesh) has no contact",
        cycles[0]["contact"][0]["force"][0].get<double>() == 0);
  const auto  &last = cycles.back();
  const auto  &c    = last["contact"][0];
  const double P    = -2 * c["force"][0].get<double>();
  const double p    = c["max_pressure"].get<double>();
  const double a    = c["active_area"].get<double>();
  const double p0   = std::sqrt(P * e_star / (M_PI * R));
  const double a0   = std::sqrt(4 * P * R / (M_PI * e_star));
  dealii::deallog << "last cycle: " << last["n_dofs"] << " DoFs, P "
                  << rounded(P, 4) << ", p_max " << rounded(p, 3)
                  << ", half-width " << rounded(a, 3) << std::endl;
  dealii::deallog << "Hertz for that P: p0 " << rounded(p0, 3)
                  << ", half-width " << rounded(a0, 3) << std::endl;
  check("p_max within 3% of Hertz's p0", std::abs(p / p0 - 1) < 0.03);
  check("half-width within 3% of Hertz's", std::abs(a / a0 - 1) < 0.03);

  const auto k    = run_example("contact_assembly",
                             "hertz_ring",
                             " --set 'Finite element/Adaptive cycles=4'"
                                " --set 'Finite element/Contact residual=false'");
  bool       none = true;
  for (const auto &cycle : k["cycles"])
    none &= cycle["contact"][0]["force"][0].get<double>() == 0;
  check("Kelly alone: no contact in any of 5 cycles", none);

  // The adjoint on the adapted mesh (hanging nodes, contact active): the
  // stress norm's gradient in the cells' Lame parameters.
  const auto g = run_example("contact_assembly",
                             "hertz_ring",
                             " --set 'Mode=verify gradient'"
                             " --set 'Design/Parameters=cell material'"
                             " --set 'Objective/Terms=stress : p=4'"
                             " --set 'Finite element/Adaptive cycles=4'");
  dealii::deallog << "Taylor test on the adapted mesh: "
                  << rate_verdict(g["gradient_check"]["min_rate"].get<double>())
                  << std::endl;
}
