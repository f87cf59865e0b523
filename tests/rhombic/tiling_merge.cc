// Merging shared joints (thesis ch. 4.8, merge error): two square cells
// side by side whose structures have joint radii p5 = 0.1 and 0.3. Without
// the merge each keeps its own joint at the shared side's midpoint (the
// material's extent along the side differs across it, 0.05 against 0.15 in
// physical units, cells of side 1); with it both get the average 0.2
// (extent 0.1 on both sides), and the joint is continuous across the side.

#include <deal.II/base/mpi.h>

#include <forma/rhombic/tiling.h>

#include "../tests.h"

#include <cmath>

using namespace dealii;
using namespace forma;
using namespace forma::rhombic;

namespace
{
  // Half the material's extent along the shared side x = 1, at a distance
  // delta from it (bisection on phi along the side from the midpoint).
  double
  extent(const TiledObject &object, const double x)
  {
    double in = 0, out = 0.3;
    for (unsigned int it = 0; it < 50; ++it)
      {
        const double t                                = 0.5 * (in + out);
        (object(Point<2>(x, 0.5 + t)) < 0 ? in : out) = t;
      }
    return in;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog(2);
  const std::vector<Quad> quads = {
    {{Point<2>(0, 0), Point<2>(1, 0), Point<2>(0, 1), Point<2>(1, 1)}},
    {{Point<2>(1, 0), Point<2>(2, 0), Point<2>(1, 1), Point<2>(2, 1)}}};
  std::vector<RhombicStructure> structures(2);
  structures[0].p[4] = 0.1;
  structures[1].p[4] = 0.3;
  const double delta = 0.01;
  for (const bool merge : {false, true})
    {
      const TiledObject object(quads, structures, {}, merge);
      const double      left = extent(object, 1 - delta),
                   right     = extent(object, 1 + delta);
      deallog << (merge ? "merged" : "not merged") << ": mismatch "
              << object.largest_joint_mismatch << ", extent left " << left
              << ", right " << right << ", |left - right| "
              << (std::abs(left - right) < 0.005 ? "< 0.005" : ">= 0.005")
              << std::endl;
    }
}
