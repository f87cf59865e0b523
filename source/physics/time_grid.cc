#include <deal.II/base/exceptions.h>
#include <deal.II/lac/full_matrix.h>

#include <forma/physics/time_grid.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace forma
{
  namespace
  {
    /**
     * Weights w with sum_k w_k d_k = P^(r)(0), r = 0 or 1, for the
     * polynomial P of degree n-1 that takes the values d_k at the scaled
     * nodes s_k, or (for k = n-1 when `last_is_slope`) the slope d_k there.
     * They solve V^T w = e_r with V the (confluent) Vandermonde matrix.
     */
    std::vector<double>
    polynomial_weights(const std::vector<double> &s,
                       const bool                 last_is_slope,
                       const unsigned int         r)
    {
      const unsigned int         n = s.size();
      dealii::FullMatrix<double> Vt(n, n);
      for (unsigned int k = 0; k < n; ++k)
        for (unsigned int m = 0; m < n; ++m)
          Vt(m, k) = last_is_slope && k == n - 1 ?
                       (m == 0 ? 0. : m * std::pow(s[k], m - 1.)) :
                       std::pow(s[k], 1. * m);
      Vt.gauss_jordan();
      std::vector<double> w(n);
      for (unsigned int k = 0; k < n; ++k)
        w[k] = Vt(k, r);
      return w;
    }
  } // namespace



  TimeGrid
  TimeGrid::uniform(const double end_time, const unsigned int n)
  {
    TimeGrid     g;
    const double dt = end_time / n;
    g.uniform_step  = dt;
    g.times.resize(n + 1);
    for (unsigned int i = 0; i <= n; ++i)
      g.times[i] = i * dt; // as the fixed-step loop has always computed it
    return g;
  }



  TimeGrid
  TimeGrid::variable()
  {
    TimeGrid g;
    g.times         = {0.};
    g.orders        = {0};
    g.uniform_steps = false;
    return g;
  }



  void
  TimeGrid::push(const double t, const unsigned int order)
  {
    AssertThrow(!times.empty() && t > times.back(),
                dealii::ExcMessage("time levels must increase"));
    AssertThrow(!uniform_steps && order >= 1 && order <= max_variable_order,
                dealii::ExcMessage("variable time steps use BDF orders 1 to " +
                                   std::to_string(max_variable_order) +
                                   " (got " + std::to_string(order) + ")."));
    times.push_back(t);
    orders.push_back(order);
  }



  unsigned int
  TimeGrid::order(const unsigned int i, const unsigned int order) const
  {
    const unsigned int q = std::min(i, order);
    return uniform_steps ? q : std::min(q, orders[i]);
  }



  double
  TimeGrid::step(const unsigned int i) const
  {
    if (i == 0 || i >= times.size())
      return 0.;
    // Uniform: the one step size, bit for bit as before the grid existed.
    if (uniform_steps)
      return uniform_step;
    return times[i] - times[i - 1];
  }



  BDFCoefficients
  TimeGrid::coefficients(const unsigned int i, const unsigned int q) const
  {
    AssertThrow(q >= 1 && q <= i,
                dealii::ExcMessage("BDF" + std::to_string(q) + " at step " +
                                   std::to_string(i) + " is not defined."));
    if (uniform_steps)
      return bdf_coefficients(q);
    if (q == 1)
      return bdf_coefficients(1);
    if (q == 2)
      {
        const double w = step(i) / step(i - 1);
        return {{-(1 + w) * (1 + w) / (1 + 2 * w), w * w / (1 + 2 * w)},
                (1 + w) / (1 + 2 * w)};
      }
    // u'(t_i) from the polynomial through t_i..t_{i-q}, in s = (t - t_i)/h.
    const double        h = step(i);
    std::vector<double> s(q + 1);
    for (unsigned int j = 0; j <= q; ++j)
      s[j] = (times[i - j] - times[i]) / h;
    const auto      w = polynomial_weights(s, false, 1);
    BDFCoefficients c{std::vector<double>(q), 1. / w[0]};
    for (unsigned int j = 1; j <= q; ++j)
      c.alpha[j - 1] = w[j] / w[0];
    return c;
  }



  TimeGrid::Extrapolation
  TimeGrid::extrapolation(const unsigned int i, const unsigned int q) const
  {
    AssertThrow(q >= 1 && q <= i && i < times.size(),
                dealii::ExcMessage("extrapolation of degree " +
                                   std::to_string(q) + " to level " +
                                   std::to_string(i) + " is not defined."));
    const double        h       = step(i);
    const bool          hermite = q == i;
    const unsigned int  n_u     = hermite ? q : q + 1;
    std::vector<double> s(q + 1);
    for (unsigned int j = 1; j <= n_u; ++j)
      s[j - 1] = (times[i - j] - times[i]) / h;
    if (hermite)
      s[q] = (times[0] - times[i]) / h; // the slope at t_0
    auto          w = polynomial_weights(s, hermite, 0);
    Extrapolation e{std::vector<double>(w.begin(), w.begin() + n_u),
                    hermite ? w[q] * h : 0., // d/dt = (1/h) d/ds
                    times[i] - times[i - n_u]};
    return e;
  }



  std::vector<unsigned int>
  TimeGrid::steps_per_order(const unsigned int order) const
  {
    std::vector<unsigned int> n(order, 0);
    for (unsigned int i = 1; i <= n_steps(); ++i)
      ++n[this->order(i, order) - 1];
    return n;
  }



  double
  TimeGrid::trapezoid_weight(const unsigned int i) const
  {
    return 0.5 * (step(i) + step(i + 1));
  }
} // namespace forma
