// The distance formulas of IPC, templated on the number type for forward
// AD (internal to the ipc sources, not installed).
#ifndef forma_source_ipc_formulas_h
#define forma_source_ipc_formulas_h

#include <forma/ipc/distance.h>

#include <array>

namespace forma
{
  namespace ipc
  {
    namespace internal
    {
      template <typename T>
      using V3 = std::array<T, 3>;

      template <typename T>
      V3<T>
      sub(const V3<T> &a, const V3<T> &b)
      {
        return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}};
      }

      template <typename T>
      T
      dot(const V3<T> &a, const V3<T> &b)
      {
        return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
      }

      template <typename T>
      V3<T>
      cross(const V3<T> &a, const V3<T> &b)
      {
        return {{a[1] * b[2] - a[2] * b[1],
                 a[2] * b[0] - a[0] * b[2],
                 a[0] * b[1] - a[1] * b[0]}};
      }

      /// Squared distance of formula `type` at the arguments x[0..].
      template <typename T>
      T
      distance_squared(const DistanceType type, const V3<T> *x)
      {
        switch (type)
          {
              case DistanceType::point_point: {
                const V3<T> d = sub(x[0], x[1]);
                return dot(d, d);
              }
              case DistanceType::point_edge: {
                const V3<T> e = sub(x[2], x[1]);
                const V3<T> c = cross(sub(x[0], x[1]), e);
                return dot(c, c) / dot(e, e);
              }
              case DistanceType::point_triangle: {
                const V3<T> n = cross(sub(x[2], x[1]), sub(x[3], x[1]));
                const T     s = dot(sub(x[0], x[1]), n);
                return s * s / dot(n, n);
              }
              case DistanceType::edge_edge: {
                const V3<T> n = cross(sub(x[1], x[0]), sub(x[3], x[2]));
                const T     s = dot(sub(x[0], x[2]), n);
                return s * s / dot(n, n);
              }
              case DistanceType::point_plane: {
                const T s = dot(sub(x[0], x[1]), x[2]);
                return s * s;
              }
          }
        return T(0.);
      }

      /**
       * Closest points and normal of a classified pair (lagged friction,
       * thesis eq. 3.26): weights w of its arguments x[0..] such that the
       * relative displacement of the closest points is sum_a w_a du_a, and
       * a (not normalized, unsigned) normal of the contact. For a plane,
       * x = (p, origin, unit normal).
       */
      template <typename T>
      void
      closest_point_frame(const DistanceType type,
                          const V3<T>       *x,
                          std::array<T, 4>  &w,
                          V3<T>             &normal)
      {
        w = {{T(1.), T(0.), T(0.), T(0.)}};
        switch (type)
          {
            case DistanceType::point_point:
              w[1]   = -1.;
              normal = sub(x[0], x[1]);
              break;
              case DistanceType::point_edge: {
                const V3<T> e = sub(x[2], x[1]);
                const T     t = dot(sub(x[0], x[1]), e) / dot(e, e);
                w[1]          = t - 1.;
                w[2]          = -t;
                normal        = sub(x[0], x[1]);
                for (unsigned int d = 0; d < 3; ++d)
                  normal[d] -= t * e[d];
                break;
              }
              case DistanceType::point_triangle: {
                const V3<T> e1 = sub(x[2], x[1]), e2 = sub(x[3], x[1]);
                const V3<T> r = sub(x[0], x[1]);
                const T a11 = dot(e1, e1), a12 = dot(e1, e2), a22 = dot(e2, e2);
                const T b1 = dot(r, e1), b2 = dot(r, e2);
                const T det = a11 * a22 - a12 * a12;
                const T l1  = (a22 * b1 - a12 * b2) / det;
                const T l2  = (a11 * b2 - a12 * b1) / det;
                w[1]        = l1 + l2 - 1.;
                w[2]        = -l1;
                w[3]        = -l2;
                normal      = cross(e1, e2);
                break;
              }
              case DistanceType::edge_edge: {
                const V3<T> ea = sub(x[1], x[0]), eb = sub(x[3], x[2]);
                const V3<T> r = sub(x[0], x[2]);
                const T a11 = dot(ea, ea), a12 = dot(ea, eb), a22 = dot(eb, eb);
                const T D = dot(ea, r), E = dot(eb, r);
                const T den = a11 * a22 - a12 * a12;
                const T sa  = (a12 * E - a22 * D) / den;
                const T tb  = (a11 * E - a12 * D) / den;
                w           = {{1. - sa, sa, tb - 1., -tb}};
                normal      = cross(ea, eb);
                break;
              }
            case DistanceType::point_plane:
              normal = x[2];
              break;
          }
      }

      /// |e_a x e_b|^2 of the edges (x0, x1), (x2, x3): the argument of
      /// the edge-edge mollifier.
      template <typename T>
      T
      edge_cross_squared(const V3<T> *x)
      {
        const V3<T> n = cross(sub(x[1], x[0]), sub(x[3], x[2]));
        return dot(n, n);
      }
    } // namespace internal
  }   // namespace ipc
} // namespace forma

#endif
