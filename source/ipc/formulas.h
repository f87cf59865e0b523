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
