#ifndef forma_rhombic_half_plane_region_h
#define forma_rhombic_half_plane_region_h

#include <array>
#include <vector>

namespace forma
{
  namespace rhombic
  {
    /// c_E x + c_nu y <= d on a plane of materials (x: E/E_b or its log,
    /// y: Poisson's ratio); (c_E, c_nu) is a unit vector, so c . x - d is
    /// a distance.
    struct HalfPlane
    {
      double c_E, c_nu, d;
    };

    using HalfPlaneRegion = std::vector<HalfPlane>;

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
