#ifndef forma_ipc_ccd_h
#define forma_ipc_ccd_h

#include <forma/ipc/distance.h>

#include <array>

namespace forma
{
  namespace ipc
  {
    /// The primitive pairs IPC checks: vertex-edge (2D and 3D),
    /// vertex-triangle and edge-edge (3D), vertex against a static plane.
    enum class PairKind : unsigned char
    {
      point_edge,
      point_triangle,
      edge_edge,
      point_plane
    };

    /// Number of vertices of a pair kind (a plane counts as none).
    unsigned int
    n_vertices(const PairKind kind);

    /// Unsigned distance of a pair at positions x (plane: x[1] = origin,
    /// x[2] = unit normal; the distance is signed, positive on the normal's
    /// side).
    double
    pair_distance(const PairKind kind, const std::array<Vec, 4> &x);

    struct CcdResult
    {
      double       time       = 1; ///< no contact on [0, time]
      unsigned int iterations = 0;
    };

    /**
     * Continuous collision detection by additive CCD (Li et al. 2021, C-IPC
     * Alg. 1): the pair moves linearly from x to x + dx over t in [0, 1].
     * Steps of length 0.9 d(t) / l_p, where l_p bounds the relative motion
     * of the two primitives, can never close the distance, so every
     * returned time is conservative: the pair does not touch on [0, time].
     * The search stops when the distance falls below `gap` times the
     * starting distance (the step then ends there), or when t reaches 1
     * (time = 1: no contact). `max_iterations` bounds grazing motions (the
     * time reached is returned). Planes (x[1] origin, x[2] unit normal, dx
     * zero for both) are solved exactly, leaving the same gap.
     */
    CcdResult
    additive_ccd(const PairKind            kind,
                 const std::array<Vec, 4> &x,
                 const std::array<Vec, 4> &dx,
                 const double              gap            = 0.1,
                 const unsigned int        max_iterations = 1000000);
  } // namespace ipc
} // namespace forma

#endif
