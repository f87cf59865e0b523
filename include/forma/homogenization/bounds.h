#ifndef forma_homogenization_bounds_h
#define forma_homogenization_bounds_h

#include <forma/homogenization/elastic_tensor.h>

#include <utility>

namespace forma
{
  /**
   * Hashin-Shtrikman bounds (thesis eqs. 5.1-5.3) on the 2D bulk and shear
   * moduli of an isotropic composite of a strong and a weak isotropic phase
   * with strong-phase volume fraction phi. For a void weak phase
   * (kappa_w = mu_w = 0) the lower bounds are 0 and the upper ones are
   * eq. 5.1; the bounds grow with phi, so phi = 1 gives the bounds for a
   * free volume fraction.
   */
  struct HashinShtrikmanBounds
  {
    double kappa_lower = 0, kappa_upper = 0, mu_lower = 0, mu_upper = 0;

    /// Upper bound on E at Poisson's ratio nu (eq. 5.2):
    /// min(2 kappa_u (1 - nu), 2 mu_u (1 + nu)).
    double
    max_young_modulus(const double nu) const;

    /**
     * Whether (kappa, mu) lies inside, allowing a relative `tolerance` of
     * the upper bounds; returns the largest violation relative to the upper
     * bounds (<= 0 inside).
     */
    double
    violation(const IsotropicModuli &m) const;
  };

  /// The bounds for `strong` and `weak` (well ordered) at fraction phi.
  HashinShtrikmanBounds
  hashin_shtrikman(const IsotropicModuli &strong,
                   const IsotropicModuli &weak,
                   const double           phi);

  /**
   * The upper bounds (kappa_upper, mu_upper) alone, for any scalar phi:
   * double, or a forward AD number (Sacado::Fad::DFad<double>, the
   * instantiated one) for their exact derivatives.
   */
  template <typename Number>
  std::pair<Number, Number>
  hashin_shtrikman_upper(const IsotropicModuli &strong,
                         const IsotropicModuli &weak,
                         const Number          &phi);

  /// The bounds of a void-material composite (eq. 5.1).
  HashinShtrikmanBounds
  hashin_shtrikman_void(const IsotropicModuli &base, const double phi);

  /**
   * The Cherkaev-Lurie-Milton shift (thesis Theorem 4.1, eq. 4.11): the
   * effective tensor of a perforated 2D medium when its base material
   * changes from `from` to `to`. In compliance form,
   * S' = (E/E') (S + t L) with t = (nu - nu') / E and L the null-Lagrangian
   * direction [[0, 1, 0], [1, 0, 0], [0, 0, -2]] (Voigt, engineering shear);
   * for isotropic results this is E'_H = E' E_H / E and
   * nu'_H = nu_H - (nu - nu') E_H / E. Exact for holes, approximate (to the
   * order of the weak phase stiffness) for a weak phase.
   */
  dealii::SymmetricTensor<4, 2>
  clm_transform(const dealii::SymmetricTensor<4, 2> &C_effective,
                const IsotropicModuli               &from,
                const IsotropicModuli               &to);
} // namespace forma

#endif
