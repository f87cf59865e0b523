#include <deal.II/base/exceptions.h>
#include <deal.II/lac/full_matrix.h>

#include <forma/ipc/distance.h>

#include "formulas.h"
#include <Sacado.hpp>

namespace forma
{
  namespace ipc
  {
    using namespace dealii;

    unsigned int
    n_arguments(const DistanceType type)
    {
      switch (type)
        {
          case DistanceType::point_point:
            return 2;
          case DistanceType::point_edge:
          case DistanceType::point_plane:
            return 3;
          default:
            return 4;
        }
    }



    DistanceStencil
    classify_point_edge(const Vec &p, const Vec &a, const Vec &b)
    {
      DistanceStencil s;
      const Vec       e  = b - a;
      const double    e2 = e.norm_square();
      const double    t  = e2 > 0 ? (p - a) * e / e2 : 0.;
      if (t <= 0)
        {
          s.type             = DistanceType::point_point;
          s.slot             = {{0, 1, 0, 0}};
          s.distance_squared = (p - a).norm_square();
        }
      else if (t >= 1)
        {
          s.type             = DistanceType::point_point;
          s.slot             = {{0, 2, 0, 0}};
          s.distance_squared = (p - b).norm_square();
        }
      else
        {
          s.type             = DistanceType::point_edge;
          s.slot             = {{0, 1, 2, 0}};
          s.distance_squared = (p - a - t * e).norm_square();
        }
      return s;
    }



    DistanceStencil
    classify_point_triangle(const Vec &p,
                            const Vec &a,
                            const Vec &b,
                            const Vec &c)
    {
      const Vec n = cross_product_3d(b - a, c - a);
      // Inside all three edges (seen along n): the plane distance.
      if (cross_product_3d(b - a, p - a) * n >= 0 &&
          cross_product_3d(c - b, p - b) * n >= 0 &&
          cross_product_3d(a - c, p - c) * n >= 0)
        {
          DistanceStencil s;
          s.type             = DistanceType::point_triangle;
          s.slot             = {{0, 1, 2, 3}};
          const double h     = (p - a) * n;
          s.distance_squared = h * h / n.norm_square();
          return s;
        }
      // Otherwise the closest point is on the boundary: the nearest edge.
      const std::array<std::array<unsigned char, 2>, 3> edges{
        {{{1, 2}}, {{2, 3}}, {{3, 1}}}};
      const std::array<const Vec *, 4> x{{&p, &a, &b, &c}};
      DistanceStencil                  best;
      best.distance_squared = std::numeric_limits<double>::max();
      for (const auto &e : edges)
        {
          DistanceStencil s = classify_point_edge(p, *x[e[0]], *x[e[1]]);
          if (s.distance_squared < best.distance_squared)
            {
              for (auto &k : s.slot)
                k = (k == 0 ? 0 : e[k - 1]);
              best = s;
            }
        }
      return best;
    }



    DistanceStencil
    classify_edge_edge(const Vec &a0,
                       const Vec &a1,
                       const Vec &b0,
                       const Vec &b1)
    {
      const Vec    ea = a1 - a0, eb = b1 - b0, r = a0 - b0;
      const Vec    n = cross_product_3d(ea, eb);
      const double A = ea * ea, B = ea * eb, C = eb * eb;
      // Non-parallel lines whose closest points lie inside both segments:
      // the line-line distance. (The parallel threshold keeps the formula
      // away from its 0/0 limit; the mollifier covers the transition.)
      if (n.norm_square() > 1e-20 * A * C)
        {
          const double D = ea * r, E = eb * r, den = A * C - B * B;
          const double s = (B * E - C * D) / den, t = (A * E - B * D) / den;
          if (s > 0 && s < 1 && t > 0 && t < 1)
            {
              DistanceStencil st;
              st.type             = DistanceType::edge_edge;
              st.slot             = {{0, 1, 2, 3}};
              const double h      = r * n;
              st.distance_squared = h * h / n.norm_square();
              return st;
            }
        }
      // Otherwise an end point is closest to the other segment.
      const std::array<const Vec *, 4>                  x{{&a0, &a1, &b0, &b1}};
      const std::array<std::array<unsigned char, 3>, 4> cases{
        {{{0, 2, 3}}, {{1, 2, 3}}, {{2, 0, 1}}, {{3, 0, 1}}}};
      DistanceStencil best;
      best.distance_squared = std::numeric_limits<double>::max();
      for (const auto &c : cases)
        {
          DistanceStencil s = classify_point_edge(*x[c[0]], *x[c[1]], *x[c[2]]);
          if (s.distance_squared < best.distance_squared)
            {
              const unsigned int n_args = n_arguments(s.type);
              for (unsigned int k = 0; k < n_args; ++k)
                s.slot[k] = c[s.slot[k]];
              best = s;
            }
        }
      return best;
    }



    double
    distance_squared(const DistanceType      type,
                     const std::vector<Vec> &x,
                     std::vector<double>    *gradient,
                     FullMatrix<double>     *hessian)
    {
      const unsigned int n = n_arguments(type);
      AssertThrow(x.size() == n, ExcMessage("wrong number of arguments"));
      using Inner = Sacado::Fad::SFad<double, 12>;
      using AD    = Sacado::Fad::SFad<Inner, 12>;
      std::array<internal::V3<AD>, 4> y;
      for (unsigned int k = 0; k < n; ++k)
        for (unsigned int d = 0; d < 3; ++d)
          y[k][d] = AD(12, 3 * k + d, Inner(12, 3 * k + d, x[k][d]));
      const AD v = internal::distance_squared(type, y.data());
      if (gradient)
        {
          gradient->resize(3 * n);
          for (unsigned int i = 0; i < 3 * n; ++i)
            (*gradient)[i] = v.dx(i).val();
        }
      if (hessian)
        {
          hessian->reinit(3 * n, 3 * n);
          for (unsigned int i = 0; i < 3 * n; ++i)
            for (unsigned int j = 0; j < 3 * n; ++j)
              (*hessian)(i, j) = v.dx(i).dx(j);
        }
      return v.val().val();
    }
  } // namespace ipc
} // namespace forma
