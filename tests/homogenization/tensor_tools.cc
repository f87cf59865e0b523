// The tensor tools of homogenization against their formulas: moduli
// conversions and the isotropic fit, the anisotropy measures (eq. 4.10),
// the rank-one laminate against thesis eq. 5.9 for nu = 0 phases, the
// Hashin-Shtrikman bounds (eqs. 5.1-5.3) in (kappa, mu) and (E, nu) form,
// and the CLM transform (eq. 4.11) in tensor and isotropic form.

#include <forma/homogenization/bounds.h>
#include <forma/homogenization/elastic_tensor.h>

#include "../tests.h"

using namespace dealii;
using namespace forma;

int
main()
{
  initlog();
  // Conversions.
  {
    const auto m = IsotropicModuli::from_young_poisson(2.0, -0.4);
    const auto f = isotropic_fit(m.tensor());
    deallog << "E, nu -> tensor -> fit: " << rounded(f.E) << ' '
            << rounded(f.nu) << ", kappa " << rounded(f.kappa) << ", mu "
            << rounded(f.mu) << std::endl;
    const auto ps =
      IsotropicModuli::of_material(1.0, 0.3, PlaneModel::plane_strain);
    deallog << "plane strain 2D moduli of (1, 0.3): E " << rounded(ps.E)
            << " (1/(1-0.09) = " << rounded(1 / 0.91) << "), nu "
            << rounded(ps.nu) << " (0.3/0.7 = " << rounded(0.3 / 0.7) << ")"
            << std::endl;
    const Anisotropy a = anisotropy(rotate(m.tensor(), 0.37));
    deallog << "rotated isotropic: a1, a2, residual < 1e-14: "
            << (a.a1 < 1e-14 && a.a2 < 1e-14 && a.residual < 1e-14)
            << std::endl;
  }
  // An orthotropic tensor: the measures and their invariance to 90 degrees.
  {
    VoigtMatrix V;
    V[0][0] = 1.0, V[1][1] = 0.8, V[0][1] = V[1][0] = 0.2, V[2][2] = 0.25;
    const Anisotropy a  = anisotropy(from_voigt(V));
    const Anisotropy a2 = anisotropy(rotate(from_voigt(V), M_PI / 2));
    deallog << "orthotropic: a1 " << rounded(a.a1) << " (0.2), a2 "
            << rounded(a.a2) << " (|0.9 - 0.2 - 0.5| = 0.2), residual "
            << rounded(a.residual) << ", same after 90 degrees: "
            << (std::abs(a.a1 - a2.a1) + std::abs(a.a2 - a2.a2) < 1e-14)
            << std::endl;
  }
  // Rank-one laminate, nu = 0 phases: thesis eq. 5.9 with the Reuss mean
  // of the strong fraction theta: diag(theta E + (1-theta) Em,
  // 1/(theta/E + (1-theta)/Em), 1/(2 (theta/E + (1-theta)/Em))) in the
  // layer frame, rotated by T(alpha).
  {
    const double E = 1, Em = 1e-3, theta = 0.7, alpha = 0.4;
    const auto   s      = IsotropicModuli::from_young_poisson(E, 0),
               w        = IsotropicModuli::from_young_poisson(Em, 0);
    const auto        L = rank_one_laminate(s.tensor(), w.tensor(), theta, 0);
    const double      reuss = 1 / (theta / E + (1 - theta) / Em);
    const VoigtMatrix V     = to_voigt(L);
    deallog << "laminate along x: "
            << (std::abs(V[0][0] - (theta * E + (1 - theta) * Em)) +
                      std::abs(V[1][1] - reuss) +
                      std::abs(V[2][2] - reuss / 2) + std::abs(V[0][1]) <
                    1e-14 ?
                  "eq. 5.9" :
                  "WRONG")
            << std::endl;
    const auto La = rank_one_laminate(s.tensor(), w.tensor(), theta, alpha);
    deallog << "laminate at alpha: equals the rotated one: "
            << ((La - rotate(L, alpha)).norm() < 1e-14) << std::endl;
    // Voigt along the layers, Reuss across: between the two phase tensors.
    deallog << "theta = 1 gives the strong phase: "
            << ((rank_one_laminate(s.tensor(), w.tensor(), 1, 0.3) - s.tensor())
                  .norm() < 1e-14)
            << std::endl;
  }
  // Hashin-Shtrikman.
  {
    const double Eb = 1.0, nub = 0.2;
    const auto   base = IsotropicModuli::from_young_poisson(Eb, nub);
    for (const double phi : {0.3, 0.7, 1.0})
      {
        const auto   b = hashin_shtrikman_void(base, phi);
        const double C1 =
          Eb / (2 * (1 - nub)) +
          Eb * (1 - phi) / (phi * (1 - nub * nub) - 2 * (1 - nub));
        const double C2 =
          Eb / (2 * (1 + nub)) +
          2 * Eb * (1 - phi) / (phi * (3 - nub) * (1 + nub) - 4 * (1 + nub));
        deallog << "void, phi " << phi << ": kappa_u " << rounded(b.kappa_upper)
                << " mu_u " << rounded(b.mu_upper) << ", eq. 5.2 C1, C2 "
                << (std::abs(C1 - b.kappa_upper) + std::abs(C2 - b.mu_upper) <
                        1e-14 ?
                      "match" :
                      "DIFFER")
                << ", E_max(nu=0) " << rounded(b.max_young_modulus(0))
                << std::endl;
      }
    // phi = 1: the triangle of eq. 5.3.
    const auto b1 = hashin_shtrikman_void(base, 1.0);
    deallog << "phi = 1: E_max(-0.5) " << rounded(b1.max_young_modulus(-0.5))
            << " = Eb (1 - 0.5)/(1 + nub) " << rounded(Eb * 0.5 / (1 + nub))
            << ", E_max(0.6) " << rounded(b1.max_young_modulus(0.6))
            << " = Eb (1 - 0.6)/(1 - nub) " << rounded(Eb * 0.4 / (1 - nub))
            << std::endl;
    // Bimaterial: equal phases collapse the bounds; lower <= upper.
    const auto weak = IsotropicModuli::from_young_poisson(1e-3, 0);
    const auto s0   = IsotropicModuli::from_young_poisson(1, 0);
    const auto bb   = hashin_shtrikman(s0, weak, 0.6);
    deallog << "bimaterial phi 0.6: kappa in [" << rounded(bb.kappa_lower)
            << ", " << rounded(bb.kappa_upper) << "], mu in ["
            << rounded(bb.mu_lower) << ", " << rounded(bb.mu_upper) << "]"
            << std::endl;
    const auto same = hashin_shtrikman(s0, s0, 0.4);
    deallog << "equal phases: bounds = phase moduli: "
            << (std::abs(same.kappa_upper - s0.kappa) +
                  std::abs(same.kappa_lower - s0.kappa) +
                  std::abs(same.mu_upper - s0.mu) +
                  std::abs(same.mu_lower - s0.mu) <
                1e-14)
            << std::endl;
  }
  // CLM: the tensor form reproduces eq. 4.11 on an isotropic result and is
  // a group action (from -> to -> from is the identity).
  {
    const auto from  = IsotropicModuli::from_young_poisson(1.0, 0.0),
               to    = IsotropicModuli::from_young_poisson(2.0, 0.35);
    const auto CH    = IsotropicModuli::from_young_poisson(0.3, -0.4);
    const auto moved = isotropic_fit(clm_transform(CH.tensor(), from, to));
    deallog << "CLM: E'_H " << rounded(moved.E) << " (2 * 0.3 = 0.6), nu'_H "
            << rounded(moved.nu)
            << " (-0.4 - (0 - 0.35) 0.3 = " << rounded(-0.4 + 0.35 * 0.3) << ")"
            << std::endl;
    VoigtMatrix V;
    V[0][0] = 0.5, V[1][1] = 0.3, V[0][1] = V[1][0] = 0.1, V[2][2] = 0.05,
    V[0][2] = V[2][0] = 0.02;
    const auto back =
      clm_transform(clm_transform(from_voigt(V), from, to), to, from);
    deallog << "CLM round trip on an anisotropic tensor: "
            << ((back - from_voigt(V)).norm() < 1e-14) << std::endl;
  }
}
