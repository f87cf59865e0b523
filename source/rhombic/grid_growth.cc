#include <deal.II/base/exceptions.h>

#include <forma/rhombic/grid_growth.h>

#include <algorithm>

namespace forma
{
  namespace rhombic
  {
    GridGrowth::GridGrowth(const unsigned int n_E, const unsigned int n_nu)
      : n_E(n_E)
      , n_nu(n_nu)
      , is_solved(n_E * n_nu, false)
      , structure(n_E * n_nu)
      , neighbours_at_try(n_E * n_nu, -1)
    {}



    void
    GridGrowth::tried(const unsigned int node)
    {
      AssertIndexRange(node, is_solved.size());
      neighbours_at_try[node] = std::max(neighbours_at_try[node], 0);
    }



    void
    GridGrowth::reached(const unsigned int node, const Parameters &p)
    {
      AssertIndexRange(node, is_solved.size());
      is_solved[node] = true;
      structure[node] = p;
    }



    std::vector<GridGrowth::Start>
    GridGrowth::next_starts()
    {
      std::vector<Start> starts;
      for (unsigned int n = 0; n < is_solved.size(); ++n)
        {
          if (is_solved[n])
            continue;
          const int    i = n / n_nu, j = n % n_nu;
          Parameters   start{};
          unsigned int count = 0;
          for (const auto &[di, dj] : {std::pair<int, int>{-1, 0},
                                       std::pair<int, int>{1, 0},
                                       std::pair<int, int>{0, -1},
                                       std::pair<int, int>{0, 1}})
            {
              const int ii = i + di, jj = j + dj;
              if (ii < 0 || jj < 0 || ii >= static_cast<int>(n_E) ||
                  jj >= static_cast<int>(n_nu))
                continue;
              const unsigned int m = ii * n_nu + jj;
              if (!is_solved[m])
                continue;
              for (unsigned int q = 0; q < start.size(); ++q)
                start[q] += structure[m][q];
              ++count;
            }
          if (count == 0 || static_cast<int>(count) <= neighbours_at_try[n])
            continue;
          neighbours_at_try[n] = count;
          for (auto &v : start)
            v /= count;
          starts.emplace_back(n, start);
        }
      return starts;
    }



    unsigned int
    GridGrowth::n_solved() const
    {
      return std::count(is_solved.begin(), is_solved.end(), true);
    }
  } // namespace rhombic
} // namespace forma
