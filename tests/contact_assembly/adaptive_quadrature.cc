// Adaptive quadrature on contact faces (thesis ch. 2.9.4) on the thesis's
// worked example: a P2 triangle with nodal displacements u_0..u_5, normal
// n = (1, 1, 1) / sqrt(3), alpha = eta = 1e-4, the integral
//   (1/alpha) int phi_0 n_0 h_eta(u . n)
// over the reference triangle (phi_0 the quadratic basis function of vertex
// 0; nodes: vertices, then edge midpoints 01, 12, 20). The thesis reports
// -0.329516 (Matlab integral2), plain order-10 Gauss -0.438527 and its
// adaptive scheme (depth 5, 10 samples) -0.329560. Here: a plain Gauss rule
// of 10 x 10 points, the adaptive rule, and its converged value (depth 14),
// plus a segment case with a known integral.

#include <deal.II/base/quadrature_lib.h>

#include <forma/contact/adaptive_quadrature.h>
#include <forma/contact/smoothing.h>

#include "../tests.h"

using namespace dealii;

int
main()
{
  initlog();
  const double alpha = 1e-4, eta = 1e-4;
  const double u[6][3] = {{0.0, 0.1, -0.05},
                          {0.1, 0.2, -0.03},
                          {-0.1, 0.0, -0.02},
                          {-0.05, 0.01, 0.02},
                          {-0.02, -0.02, 0.01},
                          {0.02, -0.03, 0.01}};
  const double n       = 1. / std::sqrt(3.);
  auto         shape   = [](const Point<2> &x, std::array<double, 6> &phi) {
    const double l[3] = {1 - x[0] - x[1], x[0], x[1]};
    for (unsigned int i = 0; i < 3; ++i)
      phi[i] = l[i] * (2 * l[i] - 1);
    phi[3] = 4 * l[0] * l[1];
    phi[4] = 4 * l[1] * l[2];
    phi[5] = 4 * l[2] * l[0];
  };
  auto gap = [&](const Point<2> &x) {
    std::array<double, 6> phi;
    shape(x, phi);
    double g = 0;
    for (unsigned int a = 0; a < 6; ++a)
      for (unsigned int d = 0; d < 3; ++d)
        g += phi[a] * u[a][d] * n;
    return g;
  };
  auto integrate = [&](const Quadrature<2> &q) {
    double sum = 0;
    for (unsigned int k = 0; k < q.size(); ++k)
      {
        std::array<double, 6> phi;
        shape(q.point(k), phi);
        sum += q.weight(k) * phi[0] * n *
               forma::contact::h_eta(gap(q.point(k)), eta) / alpha;
      }
    return sum;
  };
  auto regime = [&](const std::vector<Point<2>> &x) {
    std::vector<int> r;
    for (const auto &p : x)
      r.push_back(forma::contact::contact_regime(gap(p), 0, eta, 1, false));
    return r;
  };
  const auto plain =
    forma::contact::adaptive_quadrature<2>(true, regime, 10, 0, 10);
  const auto adaptive =
    forma::contact::adaptive_quadrature<2>(true, regime, 10, 5, 10);
  const auto converged =
    forma::contact::adaptive_quadrature<2>(true, regime, 10, 14, 10);
  const double reference = integrate(converged);
  deallog << std::setprecision(6) << "converged (depth 14): " << reference
          << std::endl;
  deallog << "plain Gauss 10x10 (" << plain.size()
          << " points): " << integrate(plain) << ", relative error "
          << std::abs(integrate(plain) - reference) / std::abs(reference)
          << std::endl;
  deallog << "adaptive depth 5: " << integrate(adaptive)
          << ", relative error below 1e-4: "
          << (std::abs(integrate(adaptive) - reference) <
                  1e-4 * std::abs(reference) ?
                "yes" :
                "no")
          << std::endl;
  double weights = 0;
  for (const double w : adaptive.get_weights())
    weights += w;
  deallog << "adaptive weights sum to the area 1/2: "
          << (std::abs(weights - 0.5) < 1e-13 ? "yes" : "no") << std::endl;

  // Segment: int_0^1 h_eta(x - 0.3) dx with eta = 1e-3, exactly
  // (0.7)^2 / 2 + eta^2 / 6.
  const double e1      = 1e-3;
  auto         regime1 = [&](const std::vector<Point<1>> &x) {
    std::vector<int> r;
    for (const auto &p : x)
      r.push_back(forma::contact::contact_regime(p[0] - 0.3, 0, e1, 1, false));
    return r;
  };
  for (const unsigned int depth : {0u, 5u, 12u})
    {
      const auto q =
        forma::contact::adaptive_quadrature<1>(false, regime1, 4, depth, 10);
      double s = 0;
      for (unsigned int k = 0; k < q.size(); ++k)
        s += q.weight(k) * forma::contact::h_eta(q.point(k)[0] - 0.3, e1);
      deallog << "segment, depth " << depth << ": relative error "
              << std::abs(s - (0.245 + e1 * e1 / 6)) / (0.245 + e1 * e1 / 6)
              << std::endl;
    }
}
