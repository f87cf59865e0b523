#include <forma/ipc/broad_phase.h>

#include <algorithm>

namespace forma
{
  namespace ipc
  {
    namespace
    {
      /// Sort and sweep over the boxes of both sets together; `same` when
      /// a and b are one set. Reports (index in a, index in b).
      std::vector<std::pair<unsigned int, unsigned int>>
      sweep(const std::vector<Box> &a,
            const std::vector<Box> &b,
            const bool              same)
      {
        std::vector<std::pair<unsigned int, unsigned int>> pairs;
        if (a.empty() || b.empty())
          return pairs;
        // The axis along which the box centers spread most.
        Box all;
        for (const auto *set : {&a, &b})
          for (const Box &x : *set)
            {
              std::array<double, 3> c;
              for (unsigned int d = 0; d < 3; ++d)
                c[d] = 0.5 * (x.lo[d] + x.hi[d]);
              all.add(c);
            }
        unsigned int axis = 0;
        for (unsigned int d = 1; d < 3; ++d)
          if (all.hi[d] - all.lo[d] > all.hi[axis] - all.lo[axis])
            axis = d;

        // Entries: (set, index), sorted by the lower bound along the axis.
        std::vector<std::pair<unsigned int, unsigned int>> order;
        order.reserve(a.size() + (same ? 0 : b.size()));
        for (unsigned int i = 0; i < a.size(); ++i)
          order.emplace_back(0, i);
        if (!same)
          for (unsigned int j = 0; j < b.size(); ++j)
            order.emplace_back(1, j);
        const auto box =
          [&](const std::pair<unsigned int, unsigned int> &e) -> const Box & {
          return e.first == 0 ? a[e.second] : b[e.second];
        };
        std::sort(order.begin(),
                  order.end(),
                  [&](const auto &x, const auto &y) {
                    const double lx = box(x).lo[axis], ly = box(y).lo[axis];
                    return lx < ly || (lx == ly && x < y);
                  });
        for (unsigned int k = 0; k < order.size(); ++k)
          {
            const Box &bk = box(order[k]);
            for (unsigned int m = k + 1;
                 m < order.size() && box(order[m]).lo[axis] <= bk.hi[axis];
                 ++m)
              {
                if (!same && order[m].first == order[k].first)
                  continue;
                if (!bk.overlaps(box(order[m])))
                  continue;
                if (same)
                  pairs.emplace_back(std::min(order[k].second, order[m].second),
                                     std::max(order[k].second,
                                              order[m].second));
                else if (order[k].first == 0)
                  pairs.emplace_back(order[k].second, order[m].second);
                else
                  pairs.emplace_back(order[m].second, order[k].second);
              }
          }
        std::sort(pairs.begin(), pairs.end());
        return pairs;
      }
    } // namespace



    std::vector<std::pair<unsigned int, unsigned int>>
    overlapping_pairs(const std::vector<Box> &a, const std::vector<Box> &b)
    {
      return sweep(a, b, false);
    }



    std::vector<std::pair<unsigned int, unsigned int>>
    overlapping_pairs(const std::vector<Box> &a)
    {
      return sweep(a, a, true);
    }
  } // namespace ipc
} // namespace forma
