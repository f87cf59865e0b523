#include <forma/rhombic/redundant_parameters.h>

#include <algorithm>
#include <set>

namespace forma
{
  namespace rhombic
  {
    unsigned int
    occupied_cells(const std::vector<SweepPoint> &points,
                   const std::array<double, 4>   &box,
                   const unsigned int             bins)
    {
      const auto cell = [&](const double x, const double lo, const double hi) {
        const int c =
          hi > lo ? static_cast<int>((x - lo) / (hi - lo) * bins) : 0;
        return static_cast<unsigned int>(
          std::clamp(c, 0, static_cast<int>(bins) - 1));
      };
      std::set<unsigned int> occupied;
      for (const auto &s : points)
        occupied.insert(cell(s.nu, box[0], box[1]) * bins +
                        cell(s.E, box[2], box[3]));
      return occupied.size();
    }



    std::vector<FixedParameter>
    find_redundant_parameters(const std::vector<SweepPoint> &isotropic,
                              const unsigned int             bins,
                              const double                   threshold)
    {
      std::vector<FixedParameter> fixed;
      if (isotropic.empty())
        return fixed;
      std::array<double, 4> box = {
        {isotropic[0].nu, isotropic[0].nu, isotropic[0].E, isotropic[0].E}};
      for (const auto &s : isotropic)
        box = {{std::min(box[0], s.nu),
                std::max(box[1], s.nu),
                std::min(box[2], s.E),
                std::max(box[3], s.E)}};
      const double full = occupied_cells(isotropic, box, bins);

      std::vector<SweepPoint> current = isotropic;
      std::vector<bool>       done(8, false);
      while (true)
        {
          FixedParameter          best{0, 0, -1, 0};
          std::vector<SweepPoint> best_slice;
          for (unsigned int i = 0; i < 8; ++i)
            {
              if (done[i])
                continue;
              std::set<double> values;
              for (const auto &s : current)
                values.insert(s.p[i]);
              if (values.size() < 2)
                continue;
              for (const double c : values)
                {
                  std::vector<SweepPoint> slice;
                  for (const auto &s : current)
                    if (s.p[i] == c)
                      slice.push_back(s);
                  const double coverage =
                    occupied_cells(slice, box, bins) / full;
                  if (coverage > best.coverage)
                    {
                      best       = {i,
                                    c,
                                    coverage,
                                    static_cast<unsigned int>(slice.size())};
                      best_slice = std::move(slice);
                    }
                }
            }
          if (best.coverage < threshold)
            return fixed;
          fixed.push_back(best);
          done[best.index] = true;
          current          = std::move(best_slice);
        }
    }
  } // namespace rhombic
} // namespace forma
