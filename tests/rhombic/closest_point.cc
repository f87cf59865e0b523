// closest_point(): the exact Euclidean projection onto a convex region of
// half-planes (the coverage D(alpha) the two-scale design projects into).
//  - the counterexample to alternating projections: y <= 0 and
//    y <= x from (-1, 1) gives (0, 0), not (-0.5, -0.5);
//  - random polygons (8 half-planes tangent to a circle, random offsets)
//    and random points: the result is feasible, satisfies the KKT
//    conditions (x - p = sum of active normals with multipliers >= 0), and
//    no point of a dense sampling of the boundary is closer;
//  - an empty region is refused with a message.

#include <forma/base/application.h>
#include <forma/rhombic/half_plane_region.h>

#include "../tests.h"

#include <cmath>
#include <random>

using namespace forma::rhombic;

namespace
{
  /// x - p as a non-negative combination of the (unit) normals active at p,
  /// up to `tol`: the optimality conditions of the projection.
  bool
  satisfies_kkt(const std::array<double, 2> &x,
                const std::array<double, 2> &p,
                const HalfPlaneRegion       &region)
  {
    const std::array<double, 2> r = {{x[0] - p[0], x[1] - p[1]}};
    std::vector<unsigned int>   active;
    for (unsigned int i = 0; i < region.size(); ++i)
      if (std::abs(region[i].c_E * p[0] + region[i].c_nu * p[1] - region[i].d) <
          1e-9)
        active.push_back(i);
    if (std::hypot(r[0], r[1]) < 1e-12)
      return true;
    // One active normal parallel to r, or r in the cone of two of them.
    for (const unsigned int i : active)
      {
        const auto  &a     = region[i];
        const double cross = a.c_E * r[1] - a.c_nu * r[0];
        if (std::abs(cross) < 1e-9 && a.c_E * r[0] + a.c_nu * r[1] > 0)
          return true;
        for (const unsigned int j : active)
          {
            const auto  &b   = region[j];
            const double det = a.c_E * b.c_nu - a.c_nu * b.c_E;
            if (std::abs(det) < 1e-12)
              continue;
            const double la = (r[0] * b.c_nu - r[1] * b.c_E) / det;
            const double lb = (a.c_E * r[1] - a.c_nu * r[0]) / det;
            if (la >= -1e-9 && lb >= -1e-9)
              return true;
          }
      }
    return false;
  }
} // namespace

int
main()
{
  initlog();
  const double    s = 1 / std::sqrt(2.);
  HalfPlaneRegion wedge{{0, 1, 0}, {-s, s, 0}};
  const auto      p = closest_point({{-1, 1}}, wedge);
  dealii::deallog << "wedge y <= 0, y <= x from (-1, 1) goes to (0, 0): "
                  << (std::hypot(p[0], p[1]) < 1e-12 ? "yes" : "no")
                  << std::endl;

  std::mt19937                           rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  unsigned int n_points = 0, n_outside = 0, n_feasible = 0, n_kkt = 0,
               n_not_beaten = 0;
  for (unsigned int polygon = 0; polygon < 20; ++polygon)
    {
      HalfPlaneRegion region;
      for (unsigned int k = 0; k < 8; ++k)
        {
          const double t = 2 * M_PI * (k + 0.8 * u(rng)) / 8;
          region.push_back({std::cos(t), std::sin(t), 0.5 + 0.5 * u(rng)});
        }
      // Boundary samples: points of the lines inside the region.
      std::vector<std::array<double, 2>> boundary;
      for (const auto &h : region)
        for (int k = -4000; k <= 4000; ++k)
          {
            const double                t = k * 1e-3;
            const std::array<double, 2> b = {
              {h.d * h.c_E - t * h.c_nu, h.d * h.c_nu + t * h.c_E}};
            if (violation(b, region) <= 1e-12)
              boundary.push_back(b);
          }
      for (unsigned int k = 0; k < 25; ++k)
        {
          const std::array<double, 2> x = {{6 * u(rng) - 3, 6 * u(rng) - 3}};
          const auto                  q = closest_point(x, region);
          ++n_points;
          n_outside += violation(x, region) > 0;
          n_feasible += violation(q, region) <= 1e-10;
          n_kkt += satisfies_kkt(x, q, region);
          const double d      = std::hypot(q[0] - x[0], q[1] - x[1]);
          bool         beaten = false;
          for (const auto &b : boundary)
            beaten |= std::hypot(b[0] - x[0], b[1] - x[1]) < d - 1e-9;
          n_not_beaten += !beaten;
        }
    }
  dealii::deallog << n_points << " random points (" << n_outside
                  << " outside) on 20 random octagons: feasible " << n_feasible
                  << ", KKT conditions hold " << n_kkt
                  << ", no boundary sample closer " << n_not_beaten
                  << std::endl;

  const HalfPlaneRegion empty{{1, 0, -1}, {-1, 0, -1}};
  try
    {
      closest_point({{0, 0}}, empty);
      dealii::deallog << "empty region: accepted" << std::endl;
    }
  catch (const std::exception &e)
    {
      dealii::deallog << "empty region refused: " << forma::error_message(e)
                      << std::endl;
    }
}
