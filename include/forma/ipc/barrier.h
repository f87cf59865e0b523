#ifndef forma_ipc_barrier_h
#define forma_ipc_barrier_h

#include <forma/contact/smoothing.h>

#include <cmath>

namespace forma
{
  /**
   * The scalar functions of incremental potential contact (Li et al. 2020;
   * thesis ch. 3.7, contact and friction paragraphs). Templated on the
   * number type so forward AD types (Sacado) differentiate them; branches
   * follow the value.
   */
  namespace ipc
  {
    using contact::value_of;

    /**
     * The clamped log barrier on the unsigned distance d:
     *   b(d) = -(d - dhat)^2 log(d / dhat) for 0 < d < dhat, 0 beyond.
     * C^2 at d = dhat, +infinity as d -> 0.
     */
    template <typename Number>
    Number
    barrier(const Number &d, const double dhat)
    {
      using std::log;
      if (value_of(d) >= dhat)
        return Number(0.);
      const Number s = d - dhat;
      return -s * s * log(d / dhat);
    }

    /// b'(d) (<= 0: a repulsive force).
    template <typename Number>
    Number
    barrier_derivative(const Number &d, const double dhat)
    {
      using std::log;
      if (value_of(d) >= dhat)
        return Number(0.);
      const Number s = d - dhat;
      return -2. * s * log(d / dhat) - s * s / d;
    }

    /// b''(d) (> 0 below dhat).
    inline double
    barrier_second_derivative(const double d, const double dhat)
    {
      if (d >= dhat)
        return 0.;
      const double s = d - dhat;
      return -2. * std::log(d / dhat) - 4. * s / d + s * s / (d * d);
    }

    /**
     * The edge-edge mollifier of IPC for nearly parallel edges: with
     * c = |e_a x e_b|^2 and the threshold eps_x = 1e-3 |e_a|^2 |e_b|^2 (rest
     * lengths), m(c) = (2 - c / eps_x) c / eps_x below eps_x, 1 above. It
     * makes the edge-edge potential C^1 where the edges turn parallel.
     */
    template <typename Number, typename Threshold>
    Number
    edge_edge_mollifier(const Number &c, const Threshold &eps_x)
    {
      if (value_of(c) >= value_of(eps_x))
        return Number(1.);
      const Number r = c / eps_x;
      return (2. - r) * r;
    }

    /**
     * The friction mollifier f_0 of lagged IPC friction (its derivative f_1
     * is the f_eta of thesis eq. 3.26): for the tangential slip y >= 0,
     *   f_0(y) = -y^3 / (3 eta^2) + y^2 / eta + eta / 3 below eta, y above,
     * so that the friction potential mu N f_0(|tau|) gives the force
     * -mu N f_1(|tau|) tau / |tau|.
     */
    template <typename Number>
    Number
    friction_f0(const Number &y, const double eta)
    {
      if (value_of(y) >= eta)
        return y;
      return -y * y * y / (3. * eta * eta) + y * y / eta + eta / 3.;
    }

    /// f_1(y) = f_0'(y) = -y^2 / eta^2 + 2 y / eta below eta, 1 above.
    inline double
    friction_f1(const double y, const double eta)
    {
      if (y >= eta)
        return 1.;
      return -y * y / (eta * eta) + 2. * y / eta;
    }

    /// f_1(y) / y, finite at y = 0: 2 / eta - y / eta^2 below eta.
    template <typename Number>
    Number
    friction_f1_over_y(const Number &y, const double eta)
    {
      if (value_of(y) >= eta)
        return 1. / y;
      return 2. / eta - y / (eta * eta);
    }

    /// d/dy (f_1(y) / y) / y: -1 / (y eta^2) below eta, -1 / y^3 above.
    inline double
    friction_f2_term(const double y, const double eta)
    {
      if (y >= eta)
        return -1. / (y * y * y);
      return -1. / (y * eta * eta);
    }
  } // namespace ipc
} // namespace forma

#endif
