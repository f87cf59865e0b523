#include <forma/ipc/ccd.h>

#include <algorithm>
#include <cmath>

namespace forma
{
  namespace ipc
  {
    unsigned int
    n_vertices(const PairKind kind)
    {
      switch (kind)
        {
          case PairKind::point_edge:
            return 3;
          case PairKind::point_plane:
            return 1;
          default:
            return 4;
        }
    }



    double
    pair_distance(const PairKind kind, const std::array<Vec, 4> &x)
    {
      switch (kind)
        {
          case PairKind::point_edge:
            return std::sqrt(
              classify_point_edge(x[0], x[1], x[2]).distance_squared);
          case PairKind::point_triangle:
            return std::sqrt(
              classify_point_triangle(x[0], x[1], x[2], x[3]).distance_squared);
          case PairKind::edge_edge:
            return std::sqrt(
              classify_edge_edge(x[0], x[1], x[2], x[3]).distance_squared);
          case PairKind::point_plane:
            return (x[0] - x[1]) * x[2];
        }
      return 0;
    }



    CcdResult
    additive_ccd(const PairKind            kind,
                 const std::array<Vec, 4> &x0,
                 const std::array<Vec, 4> &dx,
                 const double              gap,
                 const unsigned int        max_iterations)
    {
      CcdResult r;
      if (kind == PairKind::point_plane)
        {
          const double d     = pair_distance(kind, x0);
          const double speed = dx[0] * x0[2]; // normal velocity
          if (d <= 0)
            r.time = 0;
          else if (speed < 0 && d + speed < gap * d)
            r.time = (1. - gap) * d / -speed;
          return r;
        }

      // The motion relative to the mean: the distance only sees that.
      const unsigned int n     = n_vertices(kind);
      const unsigned int first = (kind == PairKind::edge_edge ? 2 : 1);
      Vec                mean;
      for (unsigned int i = 0; i < n; ++i)
        mean += dx[i];
      mean /= n;
      std::array<Vec, 4> p, x = x0;
      double             max_a = 0, max_b = 0;
      for (unsigned int i = 0; i < n; ++i)
        {
          p[i] = dx[i] - mean;
          (i < first ? max_a : max_b) =
            std::max(i < first ? max_a : max_b, p[i].norm());
        }
      // A point of primitive a moves by at most max_a, one of b by max_b:
      // their distance changes by at most l_p per unit t.
      const double l_p = max_a + max_b;
      double       d   = pair_distance(kind, x);
      if (d <= 0)
        {
          r.time = 0;
          return r;
        }
      if (l_p <= 0)
        return r;

      const double target = gap * d;
      double       t      = 0;
      double       step   = (1. - gap) * d / l_p;
      for (r.iterations = 0; r.iterations < max_iterations; ++r.iterations)
        {
          for (unsigned int i = 0; i < n; ++i)
            x[i] += step * p[i];
          d = pair_distance(kind, x);
          if (t > 0 && d < target)
            break; // stop before the last advance
          t += step;
          if (t >= 1.)
            {
              r.time = 1.;
              return r;
            }
          step = 0.9 * d / l_p;
        }
      r.time = t;
      return r;
    }
  } // namespace ipc
} // namespace forma
