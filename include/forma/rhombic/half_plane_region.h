#ifndef forma_rhombic_half_plane_region_h
#define forma_rhombic_half_plane_region_h

#include <forma/rhombic/material_map.h>

#include <array>
#include <vector>

namespace forma
{
  namespace rhombic
  {
    using HalfPlaneRegion = std::vector<MaterialMap::HalfPlane>;

    /// The largest violation max_i (c_i . x - d_i), at most 0 inside.
    double
    violation(const std::array<double, 2> &x, const HalfPlaneRegion &region);

    /**
     * The closest point of the convex region to x (Euclidean, exact): x if
     * inside, else the nearest of the feasible feet on the lines and the
     * feasible vertices (pairwise line intersections), where the closest
     * point of a convex polygon must lie. Throws if the region is empty.
     */
    std::array<double, 2>
    closest_point(const std::array<double, 2> &x,
                  const HalfPlaneRegion       &region);
  } // namespace rhombic
} // namespace forma

#endif
