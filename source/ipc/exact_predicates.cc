#include <forma/ipc/exact_predicates.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

namespace forma
{
  namespace ipc
  {
    namespace
    {
      using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

      Kernel::Point_2
      point_2(const Vec &x)
      {
        return {x[0], x[1]};
      }

      Kernel::Point_3
      point_3(const Vec &x)
      {
        return {x[0], x[1], x[2]};
      }

      /// -1, 0 or 1.
      int
      sign(const CGAL::Orientation o)
      {
        return static_cast<int>(o);
      }
    } // namespace



    bool
    segments_cross_2d(const Vec &a, const Vec &b, const Vec &c, const Vec &d)
    {
      const auto A = point_2(a), B = point_2(b), C = point_2(c), D = point_2(d);
      // c and d strictly on opposite sides of ab, and a and b of cd.
      return sign(CGAL::orientation(A, B, C)) *
                 sign(CGAL::orientation(A, B, D)) <
               0 &&
             sign(CGAL::orientation(C, D, A)) *
                 sign(CGAL::orientation(C, D, B)) <
               0;
    }



    bool
    segment_crosses_triangle(const Vec &p,
                             const Vec &q,
                             const Vec &a,
                             const Vec &b,
                             const Vec &c)
    {
      const auto P = point_3(p), Q = point_3(q), A = point_3(a), B = point_3(b),
                 C = point_3(c);
      // p and q strictly on opposite sides of the triangle's plane ...
      if (sign(CGAL::orientation(A, B, C, P)) *
            sign(CGAL::orientation(A, B, C, Q)) >=
          0)
        return false;
      // ... and the line pq strictly inside the triangle's three edges.
      const auto s1 = CGAL::orientation(P, Q, A, B),
                 s2 = CGAL::orientation(P, Q, B, C),
                 s3 = CGAL::orientation(P, Q, C, A);
      return s1 != CGAL::COPLANAR && s1 == s2 && s2 == s3;
    }
  } // namespace ipc
} // namespace forma
