// TimeGrid: uniform grids reproduce the fixed-step BDF tables bit for bit;
// variable-step BDF2 differentiates quadratics exactly for any step ratio,
// BDF3-5 polynomials of their degree on smoothly varying steps; the
// extrapolations of the error estimates (Hermite start included) are exact
// for polynomials of their degree; the scheme the simulator runs (BDF
// applied to u and to v, thesis eq. 3.12) converges at rate q for u'' = -u
// on non-uniform grids, for q = 2 to 5.

#include <forma/physics/time_grid.h>

#include "../tests.h"

#include <algorithm>
#include <cmath>
#include <string>

using namespace dealii;

void
check_uniform()
{
  const auto g     = forma::TimeGrid::uniform(0.7, 7);
  bool       equal = true;
  double     sum   = 0;
  for (unsigned int i = 1; i <= 7; ++i)
    for (unsigned int m = 1; m <= 6; ++m)
      {
        const auto a = g.bdf(i, m), b = forma::bdf_coefficients_at_step(m, i);
        equal &= a.alpha == b.alpha && a.beta == b.beta;
      }
  for (unsigned int i = 0; i <= 7; ++i)
    sum += g.trapezoid_weight(i);
  deallog << "uniform grid: tables reproduced: " << (equal ? "yes" : "no")
          << ", step " << g.step(3) << ", weights sum to " << sum << std::endl;
}

// Steps alternating long and short: ratios 3 and 1/3.
forma::TimeGrid
zigzag(const double end, const unsigned int pairs)
{
  auto         g = forma::TimeGrid::variable();
  const double h = end / (2 * pairs);
  double       t = 0;
  for (unsigned int k = 0; k < pairs; ++k)
    {
      g.push(t += 1.5 * h);
      g.push(k + 1 == pairs ? (t = end) : (t += 0.5 * h));
    }
  return g;
}

void
check_variable_exactness()
{
  const auto g   = zigzag(1., 5);
  double     err = 0;
  for (unsigned int i = 2; i <= g.n_steps(); ++i)
    {
      const auto c = g.bdf(i, 2);
      for (unsigned int p = 0; p <= 2; ++p)
        {
          double lhs = std::pow(g.time(i), p);
          for (unsigned int j = 1; j <= 2; ++j)
            lhs += c.alpha[j - 1] * std::pow(g.time(i - j), p);
          const double rhs =
            c.beta * g.step(i) * (p == 0 ? 0. : p * std::pow(g.time(i), p - 1));
          err = std::max(err, std::abs(lhs - rhs));
        }
    }
  deallog << "variable-step BDF2 exact for degree <= 2 (step ratios 3, 1/3): "
          << (err < 1e-13 ? "yes" : "no") << std::endl;
}

// Steps varying smoothly by up to 40% (BDF3-5 need bounded step ratios).
forma::TimeGrid
smooth(const double end, const unsigned int n)
{
  auto                g = forma::TimeGrid::variable();
  std::vector<double> t{0.};
  for (unsigned int k = 1; k <= n; ++k)
    t.push_back(t.back() + 1 + 0.4 * std::sin(0.7 * k));
  for (unsigned int k = 1; k <= n; ++k)
    g.push(end * t[k] / t[n]);
  return g;
}

// Largest miss of BDF-q's derivative (beta h udot = u^i + sum alpha u^{i-j})
// and of the degree-q extrapolation on monomials up to degree q.
void
check_higher_orders()
{
  const auto g   = smooth(1., 12);
  double     err = 0, extrapolation_err = 0, constant_err = 0;
  for (unsigned int q = 3; q <= 5; ++q)
    for (unsigned int i = q; i <= g.n_steps(); ++i)
      {
        const auto c = g.coefficients(i, q);
        const auto P = g.extrapolation(i, q);
        for (unsigned int p = 0; p <= q; ++p)
          {
            const auto u    = [&](const double t) { return std::pow(t, p); };
            const auto udot = [&](const double t) {
              return p == 0 ? 0. : p * std::pow(t, p - 1.);
            };
            double lhs = u(g.time(i)), extrapolated = P.v0 * udot(0.);
            for (unsigned int j = 1; j <= q; ++j)
              lhs += c.alpha[j - 1] * u(g.time(i - j));
            for (unsigned int j = 1; j <= P.u.size(); ++j)
              extrapolated += P.u[j - 1] * u(g.time(i - j));
            err =
              std::max(err,
                       std::abs(lhs - c.beta * g.step(i) * udot(g.time(i))));
            extrapolation_err = std::max(extrapolation_err,
                                         std::abs(extrapolated - u(g.time(i))));
          }
        // On t^(q+1) (whose u^(q+1)/(q+1)! is 1) the misses are the error
        // terms the estimates assume: -beta h pi_q and span pi_q (the
        // initial velocity of the Hermite start is 0 there).
        const auto u  = [&](const double t) { return std::pow(t, q + 1.); };
        double     pi = 1, lhs = u(g.time(i)), extrapolated = 0;
        for (unsigned int j = 1; j <= q; ++j)
          {
            pi *= g.time(i) - g.time(i - j);
            lhs += c.alpha[j - 1] * u(g.time(i - j));
          }
        for (unsigned int j = 1; j <= P.u.size(); ++j)
          extrapolated += P.u[j - 1] * u(g.time(i - j));
        const double bh = c.beta * g.step(i);
        constant_err    = std::max(
          {constant_err,
              std::abs(lhs - bh * (q + 1) * std::pow(g.time(i), q) + bh * pi),
              std::abs(u(g.time(i)) - extrapolated - P.span * pi)});
      }
  deallog << "variable-step BDF3-5 exact for their degree: "
          << (err < 1e-12 ? "yes" : "no")
          << "; extrapolations (Hermite at i = q) exact: "
          << (extrapolation_err < 1e-12 ? "yes" : "no") << std::endl;
  deallog << "error terms -beta h pi_q and span pi_q on t^(q+1): "
          << (constant_err < 1e-12 ? "yes" : "no") << std::endl;
}

// Each step keeps the order it was pushed with (capped by the run's order
// and by i); a popped step's order goes with it.
void
check_stored_orders()
{
  auto g = forma::TimeGrid::variable();
  g.push(0.1, 1);
  g.push(0.2, 3); // capped by i = 2
  g.push(0.3, 3);
  g.push(0.45, 4);
  g.pop(); // rejected
  g.push(0.4, 2);
  g.push(0.5, 5);
  std::string orders;
  for (unsigned int i = 1; i <= g.n_steps(); ++i)
    orders += std::to_string(g.order(i, 4)) + ' ';
  const auto counts = g.steps_per_order(4);
  deallog << "orders " << orders << "(cap 4); steps per order " << counts[0]
          << ' ' << counts[1] << ' ' << counts[2] << ' ' << counts[3]
          << "; step 4 reads " << g.bdf(4, 4).alpha.size()
          << " levels; last time " << g.time(g.n_steps()) << std::endl;
}

// u'' = -u, u(0) = 1, v(0) = 0 with the simulator's inertia form:
// (u^i + w) / (beta h)^2 = -u^i, w = sum_j alpha_j (u^{i-j} + beta h v^{i-j}).
// `exact_start`: levels 1..order-1 take the exact solution, so that the
// lower-order start does not hide the order.
double
oscillator_error(const forma::TimeGrid &g,
                 const unsigned int     order       = 2,
                 const bool             exact_start = false)
{
  std::vector<double> u{1.}, v{0.};
  for (unsigned int i = 1; i <= g.n_steps(); ++i)
    {
      if (exact_start && i < order)
        {
          u.push_back(std::cos(g.time(i)));
          v.push_back(-std::sin(g.time(i)));
          continue;
        }
      const auto   c  = g.bdf(i, order);
      const double bh = c.beta * g.step(i);
      double       w = 0, s = 0;
      for (unsigned int j = 1; j <= c.alpha.size(); ++j)
        {
          w += c.alpha[j - 1] * (u[i - j] + bh * v[i - j]);
          s += c.alpha[j - 1] * u[i - j];
        }
      u.push_back(-w / (1 + bh * bh));
      v.push_back((u.back() + s) / bh);
    }
  const double T = g.time(g.n_steps());
  return std::hypot(u.back() - std::cos(T), v.back() + std::sin(T));
}

void
check_convergence()
{
  double previous = 0;
  for (unsigned int pairs = 20; pairs <= 160; pairs *= 2)
    {
      const double e = oscillator_error(zigzag(2., pairs));
      deallog << "u'' = -u on " << 2 * pairs << " zigzag steps: error " << e;
      if (previous > 0)
        deallog << ", rate " << std::log2(previous / e);
      deallog << std::endl;
      previous = e;
    }
}

// Orders 3-5 on smooth grids, from exact starting levels.
void
check_higher_order_convergence()
{
  for (unsigned int q = 3; q <= 5; ++q)
    {
      const double coarse = oscillator_error(smooth(2., 80), q, true),
                   fine   = oscillator_error(smooth(2., 160), q, true);
      deallog << "BDF" << q << " on 80 -> 160 smooth steps: rate "
              << std::log2(coarse / fine) << std::endl;
    }
}

int
main()
{
  initlog(3);
  check_uniform();
  check_variable_exactness();
  check_higher_orders();
  check_stored_orders();
  check_convergence();
  check_higher_order_convergence();
}
