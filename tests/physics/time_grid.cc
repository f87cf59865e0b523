// TimeGrid: uniform grids reproduce the fixed-step BDF tables bit for bit;
// variable-step BDF2 differentiates quadratics exactly for any step ratio;
// the scheme the simulator runs (BDF applied to u and to v, thesis eq.
// 3.12) converges at rate 2 on non-uniform grids for u'' = -u.

#include <forma/physics/time_grid.h>

#include "../tests.h"

#include <cmath>

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

// u'' = -u, u(0) = 1, v(0) = 0 with the simulator's inertia form:
// (u^i + w) / (beta h)^2 = -u^i, w = sum_j alpha_j (u^{i-j} + beta h v^{i-j}).
double
oscillator_error(const forma::TimeGrid &g)
{
  std::vector<double> u{1.}, v{0.};
  for (unsigned int i = 1; i <= g.n_steps(); ++i)
    {
      const auto   c  = g.bdf(i, 2);
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

int
main()
{
  initlog(3);
  check_uniform();
  check_variable_exactness();
  check_convergence();
}
