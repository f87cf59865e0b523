#include <deal.II/base/exceptions.h>

#include <forma/rhombic/half_plane_region.h>

#include <cmath>
#include <limits>

namespace forma
{
  namespace rhombic
  {
    double
    violation(const std::array<double, 2> &x, const HalfPlaneRegion &region)
    {
      double v = -std::numeric_limits<double>::infinity();
      for (const auto &h : region)
        v = std::max(v,
                     (h.c_E * x[0] + h.c_nu * x[1] - h.d) /
                       std::hypot(h.c_E, h.c_nu));
      return region.empty() ? 0. : v;
    }



    std::array<double, 2>
    closest_point(const std::array<double, 2> &x, const HalfPlaneRegion &region)
    {
      // Feasibility up to round-off of the line intersections.
      const double tolerance = 1e-12 * (1 + std::hypot(x[0], x[1]));
      if (violation(x, region) <= tolerance)
        return x;
      std::array<double, 2> best{};
      double     best_distance = std::numeric_limits<double>::infinity();
      const auto consider      = [&](const std::array<double, 2> &p) {
        const double distance = std::hypot(p[0] - x[0], p[1] - x[1]);
        if (distance < best_distance && violation(p, region) <= tolerance)
          {
            best          = p;
            best_distance = distance;
          }
      };
      for (const auto &h : region)
        {
          const double n2 = h.c_E * h.c_E + h.c_nu * h.c_nu;
          const double v  = (h.c_E * x[0] + h.c_nu * x[1] - h.d) / n2;
          consider({{x[0] - v * h.c_E, x[1] - v * h.c_nu}});
        }
      for (unsigned int i = 0; i < region.size(); ++i)
        for (unsigned int j = i + 1; j < region.size(); ++j)
          {
            const auto  &a = region[i], &b = region[j];
            const double det = a.c_E * b.c_nu - a.c_nu * b.c_E;
            if (std::abs(det) >
                1e-14 * std::hypot(a.c_E, a.c_nu) * std::hypot(b.c_E, b.c_nu))
              consider({{(a.d * b.c_nu - a.c_nu * b.d) / det,
                         (a.c_E * b.d - a.d * b.c_E) / det}});
          }
      AssertThrow(best_distance < std::numeric_limits<double>::infinity(),
                  dealii::ExcMessage(
                    "closest_point: the coverage region (" +
                    std::to_string(region.size()) +
                    " half-planes) is empty; no material can be projected "
                    "into it."));
      return best;
    }
  } // namespace rhombic
} // namespace forma
