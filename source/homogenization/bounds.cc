#include <deal.II/base/exceptions.h>
#include <deal.II/differentiation/ad/sacado_product_types.h>

#include <forma/homogenization/bounds.h>

#include <Sacado.hpp>

#include <algorithm>
#include <cmath>
#include <tuple>

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



  template <typename Number>
  std::pair<Number, Number>
  hashin_shtrikman_upper(const IsotropicModuli &s,
                         const IsotropicModuli &w,
                         const Number          &phi)
  {
    // Written so that an equal or void weak phase needs no division by zero.
    const double dk = w.kappa - s.kappa, dm = w.mu - s.mu;
    const Number rest  = 1. - phi;
    Number       kappa = s.kappa, mu = s.mu;
    if (dk != 0)
      kappa += rest / (1 / dk + phi / (s.kappa + s.mu));
    if (dm != 0)
      mu += rest / (1 / dm +
                    phi * (s.kappa + 2 * s.mu) / (2 * s.mu * (s.kappa + s.mu)));
    return {kappa, mu};
  }



  template std::pair<double, double>
  hashin_shtrikman_upper(const IsotropicModuli &,
                         const IsotropicModuli &,
                         const double &);
  template std::pair<Sacado::Fad::DFad<double>, Sacado::Fad::DFad<double>>
  hashin_shtrikman_upper(const IsotropicModuli &,
                         const IsotropicModuli &,
                         const Sacado::Fad::DFad<double> &);



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
    std::tie(b.kappa_upper, b.mu_upper) = hashin_shtrikman_upper(s, w, phi);
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
