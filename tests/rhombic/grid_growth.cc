// The map construction's growth over an (E, nu) grid (GridGrowth, thesis
// ch. 4.6.3) with a mock inverse solve on a 4 x 4 grid, structure = (i, j)
// of the node reached and the start it came from. The continuation
// starts nodes 0 and 6 from their previous angle's structures; 0 reaches,
// 6 fails. Node 6 then succeeds from its solved neighbours' mean, node 5
// only from 3 or more neighbours (it is first started from 2, so only the
// retry covers it), node 13 never: it is tried again each time its count
// of solved neighbours grows, never twice with one count, and the growth
// ends with it unsolved.

#include <forma/rhombic/grid_growth.h>

#include "../tests.h"

using namespace dealii;
using namespace forma::rhombic;

int
main()
{
  initlog();
  const unsigned int        n_E = 4, n_nu = 4;
  GridGrowth                growth(n_E, n_nu);
  std::vector<unsigned int> tries(n_E * n_nu, 0);

  // The mock solve: reached unless the rules above say otherwise.
  const auto solve = [&](const unsigned int            node,
                         const GridGrowth::Parameters &start,
                         const unsigned int            neighbours) {
    ++tries[node];
    growth.tried(node);
    const bool reached = (node == 5 ? neighbours >= 3 : node != 13) &&
                         !(node == 6 && neighbours == 0);
    if (reached)
      growth.reached(node,
                     {{double(node / n_nu),
                       double(node % n_nu),
                       start[0],
                       start[1],
                       0,
                       0,
                       0,
                       0}});
    return reached;
  };

  GridGrowth::Parameters previous{};
  solve(0, previous, 0);
  solve(6, previous, 0);
  deallog << "continuation: " << growth.n_solved() << " solved" << std::endl;

  unsigned int round = 0;
  while (true)
    {
      const auto starts = growth.next_starts();
      if (starts.empty())
        break;
      deallog << "round " << ++round << ':';
      for (const auto &[n, start] : starts)
        {
          // The start is the mean of the solved neighbours' structures.
          unsigned int count  = 0;
          double       mean_i = 0, mean_j = 0;
          for (const unsigned int m : {n - n_nu, n + n_nu, n - 1, n + 1})
            if (m < n_E * n_nu &&
                (m / n_nu == n / n_nu || m % n_nu == n % n_nu) &&
                growth.solved()[m])
              mean_i += m / n_nu, mean_j += m % n_nu, ++count;
          const bool mean_ok = std::abs(start[0] - mean_i / count) < 1e-12 &&
                               std::abs(start[1] - mean_j / count) < 1e-12;
          const bool reached = solve(n, start, count);
          deallog << ' ' << n << " (" << count << " neighbours, mean "
                  << (mean_ok ? "ok" : "WRONG") << ", "
                  << (reached ? "reached" : "failed") << ')';
        }
      deallog << std::endl;
    }

  deallog << "solved " << growth.n_solved() << " of " << n_E * n_nu
          << "; tries per node:";
  for (const unsigned int t : tries)
    deallog << ' ' << t;
  deallog << std::endl;
  deallog << "node 5 reached from: (" << growth.structures()[5][2] << ", "
          << growth.structures()[5][3] << ")" << std::endl;
}
