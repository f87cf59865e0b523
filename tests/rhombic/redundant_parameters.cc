// The redundant-parameter test (thesis ch. 4.6.2, Fig. 4.9) on synthetic
// sweep samples whose (nu, E) depend on p2 and p3 only, where p4 = 0.7
// loses the samples with p2 = 0.3: p1 is redundant (any value keeps all
// the coverage), then p4 at 0.5; p2 and p3 each cut it to 1/3 and 1/2.

#include <forma/rhombic/redundant_parameters.h>

#include "../tests.h"

using namespace dealii;
using namespace forma::rhombic;

int
main()
{
  initlog();
  std::vector<SweepPoint> samples;
  for (const double p1 : {0.2, 0.4})
    for (const double p2 : {0.1, 0.2, 0.3})
      for (const double p3 : {0.3, 0.6})
        for (const double p4 : {0.5, 0.7})
          if (p4 == 0.5 || p2 < 0.25)
            samples.push_back(
              {{{p1, p2, p3, p4, 0.3, 0.1, 0.1, 0.1}}, p2, 0.1 * p3});
  deallog << samples.size() << " isotropic samples" << std::endl;
  for (const double threshold : {0.9, 0.4, 0.1})
    {
      deallog << "threshold " << threshold << ':';
      for (const auto &f : find_redundant_parameters(samples, 12, threshold))
        deallog << " p" << f.index + 1 << " = " << f.value << " (coverage "
                << f.coverage << ", " << f.samples << " samples)";
      deallog << std::endl;
    }
}
