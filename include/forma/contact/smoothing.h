#ifndef forma_contact_smoothing_h
#define forma_contact_smoothing_h

#include <cmath>
#include <type_traits>

namespace forma
{
  /**
   * The smoothing functions of smoothed penalty contact and friction (thesis
   * eqs. 2.8, 2.11, 2.20; Eck et al. 2005). Templated on the number type so
   * forward AD types (Sacado) differentiate them; branches follow the value.
   */
  namespace contact
  {
    /// The value of a double or of an AD number (its `val()`).
    template <typename Number>
    double
    value_of(const Number &x)
    {
      if constexpr (std::is_arithmetic_v<Number>)
        return x;
      else
        return value_of(x.val());
    }

    /// h_eta (eq. 2.8): a C^1 approximation of max(0, y).
    template <typename Number>
    Number
    h_eta(const Number &y, const double eta)
    {
      const double v = value_of(y);
      if (v <= -eta)
        return Number(0.);
      if (v >= eta)
        return y;
      return y * y / (4. * eta) + y / 2. + eta / 4.;
    }

    /// h_eta'(y).
    inline double
    h_eta_derivative(const double y, const double eta)
    {
      if (y <= -eta)
        return 0.;
      if (y >= eta)
        return 1.;
      return y / (2. * eta) + 0.5;
    }

    /// H_eta with H_eta' = h_eta, H_eta(-eta) = 0: the penalty potential.
    template <typename Number>
    Number
    h_eta_integral(const Number &y, const double eta)
    {
      const double v = value_of(y);
      if (v <= -eta)
        return Number(0.);
      if (v >= eta)
        return y * y / 2. + eta * eta / 6.;
      const Number s = y + eta;
      return s * s * s / (12. * eta);
    }

    /**
     * The smoothed norm N_eta of eq. 2.11 has the gradient N_eta'(y) =
     * f(|y|^2) y: f = 1 / |y| outside the ball of radius eta, f = 3 / (2 eta)
     * - |y|^2 / (2 eta^3) inside (C^1 across). Returns f from r2 = |y|^2.
     */
    template <typename Number>
    Number
    smoothed_norm_factor(const Number &r2, const double eta)
    {
      using std::sqrt;
      if (value_of(r2) >= eta * eta)
        return 1. / sqrt(r2);
      return 3. / (2. * eta) - r2 / (2. * eta * eta * eta);
    }

    /// N_eta(y) of eq. 2.11 (scalar |y| given as r >= 0).
    inline double
    smoothed_norm(const double r, const double eta)
    {
      if (r >= eta)
        return r;
      return -std::pow(r, 4) / (8. * eta * eta * eta) +
             3. * r * r / (4. * eta) + 3. * eta / 8.;
    }

    /**
     * g of the parallel alignment objective (eq. 2.20): 1 at z = 0, 0 at
     * |z| = epsilon, then decreasing linearly with slope beta. The cubic
     * pieces use a = -beta/epsilon^2 + 2/epsilon^3, b = -a epsilon -
     * 1/epsilon^2 as printed, mirrored for z < 0.
     */
    template <typename Number>
    Number
    alignment_g(const Number &z, const double epsilon, const double beta)
    {
      const double v = value_of(z);
      const double a = -beta / (epsilon * epsilon) + 2. / std::pow(epsilon, 3);
      const double b = -a * epsilon - 1. / (epsilon * epsilon);
      if (v <= -epsilon)
        return beta * (z + epsilon);
      if (v <= 0)
        return -a * z * z * z + b * z * z + 1.;
      if (v <= epsilon)
        return a * z * z * z + b * z * z + 1.;
      return -beta * (z - epsilon);
    }
  } // namespace contact
} // namespace forma

#endif
