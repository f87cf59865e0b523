#ifndef forma_ipc_broad_phase_h
#define forma_ipc_broad_phase_h

#include <array>
#include <utility>
#include <vector>

namespace forma
{
  namespace ipc
  {
    /// An axis-aligned box in 3D (2D problems use z = 0).
    struct Box
    {
      std::array<double, 3> lo{{1e300, 1e300, 1e300}};
      std::array<double, 3> hi{{-1e300, -1e300, -1e300}};

      /// Grow to contain the point p.
      template <typename Point>
      void
      add(const Point &p)
      {
        for (unsigned int d = 0; d < 3; ++d)
          {
            lo[d] = std::min(lo[d], double(p[d]));
            hi[d] = std::max(hi[d], double(p[d]));
          }
      }

      /// Grow by r in every direction.
      void
      inflate(const double r)
      {
        for (unsigned int d = 0; d < 3; ++d)
          {
            lo[d] -= r;
            hi[d] += r;
          }
      }

      bool
      overlaps(const Box &o) const
      {
        for (unsigned int d = 0; d < 3; ++d)
          if (lo[d] > o.hi[d] || o.lo[d] > hi[d])
            return false;
        return true;
      }
    };

    /**
     * Broad phase by sort and sweep along the axis of largest spread: every
     * pair (i, j) with a[i] and b[j] overlapping, sorted. O((n + k) log n)
     * for n boxes and k overlaps.
     */
    std::vector<std::pair<unsigned int, unsigned int>>
    overlapping_pairs(const std::vector<Box> &a, const std::vector<Box> &b);

    /// The same within one set: pairs i < j.
    std::vector<std::pair<unsigned int, unsigned int>>
    overlapping_pairs(const std::vector<Box> &a);
  } // namespace ipc
} // namespace forma

#endif
