#ifndef forma_ipc_exact_predicates_h
#define forma_ipc_exact_predicates_h

#include <forma/ipc/distance.h>

namespace forma
{
  namespace ipc
  {
    /**
     * Whether two segments, or a segment and a triangle, cross: meet at a
     * point inside both, not merely touch. Decided exactly with CGAL's
     * filtered orientation predicates, so that coplanar (collinear)
     * primitives whose coordinates were rounded, such as neighbouring
     * triangles of a turned body's flat face, are never taken for
     * crossing ones; the floating-point signs of their near-zero volumes
     * are noise.
     */
    bool
    segments_cross_2d(const Vec &a, const Vec &b, const Vec &c, const Vec &d);

    bool
    segment_crosses_triangle(const Vec &p,
                             const Vec &q,
                             const Vec &a,
                             const Vec &b,
                             const Vec &c);
  } // namespace ipc
} // namespace forma

#endif
