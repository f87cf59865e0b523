#include <deal.II/base/exceptions.h>

#include <forma/homogenization/bounds.h>

#include <algorithm>
#include <cmath>

namespace forma
{
  using namespace dealii;

  double
  HashinShtrikmanBounds::max_young_modulus(const double nu) const
  {
    return std::max(0.,
                    std::min(2 * kappa_upper * (1 - nu),
                             2 * mu_upper * (1 + nu)));
  }



  double
  HashinShtrikmanBounds::violation(const IsotropicModuli &m) const
  {
    return std::max({(m.kappa - kappa_upper) / kappa_upper,
                     (m.mu - mu_upper) / mu_upper,
                     (kappa_lower - m.kappa) / kappa_upper,
                     (mu_lower - m.mu) / mu_upper});
  }



  HashinShtrikmanBounds
  hashin_shtrikman(const IsotropicModuli &s,
                   const IsotropicModuli &w,
                   const double           phi)
  {
    AssertThrow(phi >= 0 && phi <= 1,
                ExcMessage("volume fraction " + std::to_string(phi) +
                           " is outside [0, 1]"));
    AssertThrow(s.kappa >= w.kappa && s.mu >= w.mu,
                ExcMessage("Hashin-Shtrikman bounds need well-ordered phases: "
                           "the strong phase must have the larger bulk and "
                           "shear moduli"));
    HashinShtrikmanBounds b;
    // Written so that an equal or void weak phase needs no division by zero.
    const double dk = w.kappa - s.kappa, dm = w.mu - s.mu;
    b.kappa_upper = dk == 0 ?
                      s.kappa :
                      s.kappa + (1 - phi) / (1 / dk + phi / (s.kappa + s.mu));
    b.mu_upper =
      dm == 0 ? s.mu :
                s.mu + (1 - phi) / (1 / dm + phi * (s.kappa + 2 * s.mu) /
                                               (2 * s.mu * (s.kappa + s.mu)));
    if (w.kappa + w.mu > 0 && w.mu > 0)
      {
        b.kappa_lower =
          dk == 0 ? w.kappa :
                    w.kappa + phi / (-1 / dk + (1 - phi) / (w.kappa + w.mu));
        b.mu_lower =
          dm == 0 ? w.mu :
                    w.mu + phi / (-1 / dm + (1 - phi) * (w.kappa + 2 * w.mu) /
                                              (2 * w.mu * (w.kappa + w.mu)));
      }
    return b;
  }



  HashinShtrikmanBounds
  hashin_shtrikman_void(const IsotropicModuli &base, const double phi)
  {
    return hashin_shtrikman(base, IsotropicModuli(), phi);
  }



  SymmetricTensor<4, 2>
  clm_transform(const SymmetricTensor<4, 2> &C_effective,
                const IsotropicModuli       &from,
                const IsotropicModuli       &to)
  {
    VoigtMatrix  S = invert(to_voigt(C_effective));
    const double t = (from.nu - to.nu) / from.E;
    S[0][1] += t;
    S[1][0] += t;
    S[2][2] -= 2 * t;
    return (to.E / from.E) * from_voigt(invert(S));
  }
} // namespace forma
