#include <deal.II/base/exceptions.h>

#include <forma/rhombic/coverage_region.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace forma
{
  namespace rhombic
  {
    CoverageRegion::CoverageRegion(const std::vector<HalfPlaneRegion> &pieces,
                                   const bool   logarithmic,
                                   const double base_nu)
      : log_E(logarithmic)
      , shear(logarithmic ? base_nu : 0)
    {
      for (const auto &piece : pieces)
        {
          if (piece.empty())
            continue;
          HalfPlaneRegion planes;
          for (const auto &h : piece)
            {
              // On a linear axis c_E E + c_nu (nu - s E) <= d is a
              // half-plane in (E, nu) itself.
              const HalfPlane g = {
                logarithmic ? h.c_E : h.c_E - base_nu * h.c_nu, h.c_nu, h.d};
              const double n = std::hypot(g.c_E, g.c_nu);
              planes.push_back({g.c_E / n, g.c_nu / n, g.d / n});
            }
          convex_pieces.push_back(planes);
        }
    }



    std::array<double, 2>
    CoverageRegion::coordinates(const std::array<double, 2> &m) const
    {
      // E <= 0 lies outside any region on the log axis, far away.
      const double x =
        log_E ? std::log(std::max(m[0], std::numeric_limits<double>::min())) :
                m[0];
      return {{x, m[1] - shear * m[0]}};
    }



    std::array<double, 2>
    CoverageRegion::material(const std::array<double, 2> &w) const
    {
      const double E = log_E ? std::exp(w[0]) : w[0];
      return {{E, w[1] + shear * E}};
    }



    double
    CoverageRegion::violation(const std::array<double, 2> &m) const
    {
      if (empty())
        return 0;
      const auto w = coordinates(m);
      double     v = std::numeric_limits<double>::infinity();
      for (const auto &planes : convex_pieces)
        v = std::min(v, rhombic::violation(w, planes));
      return v;
    }



    bool
    CoverageRegion::contains(const std::array<double, 2> &m,
                             const double                 tolerance) const
    {
      return !empty() && violation(m) <= tolerance;
    }



    std::array<double, 2>
    CoverageRegion::closest_point(const std::array<double, 2> &m) const
    {
      if (!empty() && violation(m) <= 0)
        return m; // exactly, not through the log and back
      AssertThrow(!empty(),
                  dealii::ExcMessage("closest_point: the coverage region is "
                                     "empty; no material can be projected "
                                     "into it."));
      const auto            w = coordinates(m);
      std::array<double, 2> best{};
      double best_distance = std::numeric_limits<double>::infinity();
      for (const auto &planes : convex_pieces)
        {
          const auto   q = rhombic::closest_point(w, planes);
          const double d = std::hypot(q[0] - w[0], q[1] - w[1]);
          if (d < best_distance)
            {
              best_distance = d;
              best          = q;
            }
        }
      return material(best);
    }



    double
    CoverageRegion::penalty(const std::array<double, 2> &m,
                            const double                 tau,
                            std::array<double, 2>       &gradient) const
    {
      if (empty())
        return 0;
      const std::array<double, 2> w = coordinates(m);
      // dw/dm: x' = 1/E on the log axis (0 where coordinates() clamps E);
      // the sheared nu falls with E.
      const double          dx_dE = !log_E ? 1. :
                                    m[0] > std::numeric_limits<double>::min() ?
                                             1 / m[0] :
                                             0.;
      double                least = std::numeric_limits<double>::infinity();
      std::array<double, 2> least_gradient = {{0, 0}};
      for (const auto &planes : convex_pieces)
        {
          double                P = 0;
          std::array<double, 2> g = {{0, 0}};
          for (const auto &h : planes)
            {
              const double v = (h.c_E * w[0] + h.c_nu * w[1] - h.d) / tau;
              if (v <= 0)
                continue;
              P += v * v;
              g[0] += 2 * v / tau * (h.c_E * dx_dE - h.c_nu * shear);
              g[1] += 2 * v / tau * h.c_nu;
            }
          if (P < least)
            {
              least          = P;
              least_gradient = g;
            }
        }
      gradient[0] += least_gradient[0];
      gradient[1] += least_gradient[1];
      return least;
    }
  } // namespace rhombic
} // namespace forma
