// An elastic ball dropped on a floor plane (IPC, frictionless, undamped):
// its rebound height (center of mass, as a fraction of the drop) behaves
// like the time integrator says it should. BDF1 dissipates much more than
// BDF2 at the same step, halving the step brings both closer to a full
// rebound, and BDF2 keeps most of the energy; the floor never touches.

#include "ipc_tests.h"

#include <cmath>

using namespace dealii;

double
rebound(const unsigned int order, const double dt)
{
  auto sim = make_ipc_simulator<2>(
    "subsection Mesh\n set Generator = hyper_ball\n"
    " set Generator arguments = 0, 0.7 : 0.5 : true\n"
    " set Initial refinement = 2\nend\n"
    "subsection Material\n set Model = neo-hookean\n"
    " set Bodies = * : E = 1e6, nu = 0.3, density = 1000\nend\n"
    "subsection Loads\n set Gravity = 0, -9.81\nend\n"
    "subsection Time\n set Problem = transient\n set End time = 0.6\n"
    " set Time step = " +
    std::to_string(dt) + "\n set BDF order = " + std::to_string(order) +
    "\nend\n"
    "subsection IPC\n set Enabled = true\n"
    " set Obstacles = plane : 0, 0 : 0, 1\nend\n");
  sim.run();
  const auto  &steps        = sim.steps();
  unsigned int low          = 0;
  double       min_distance = 1;
  for (unsigned int i = 0; i < steps.size(); ++i)
    {
      if (steps[i].mean_displacement[1] < steps[low].mean_displacement[1])
        low = i;
      if (!steps[i].contact.is_null() &&
          !steps[i].contact["min_distance"].is_null())
        min_distance =
          std::min(min_distance, double(steps[i].contact["min_distance"]));
    }
  double peak = steps[low].mean_displacement[1];
  for (unsigned int i = low; i < steps.size(); ++i)
    peak = std::max(peak, steps[i].mean_displacement[1]);
  AssertThrow(min_distance > 0, ExcMessage("the ball touched the floor"));
  // The ball's lowest point starts 0.2 above the floor.
  return (peak + 0.2) / 0.2;
}

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const double r1 = rebound(1, 0.01), r1h = rebound(1, 0.005);
  const double r2 = rebound(2, 0.01), r2h = rebound(2, 0.005);
  deallog << "rebound / drop height: BDF1 dt = 0.01: " << rounded(r1, 2)
          << ", dt = 0.005: " << rounded(r1h, 2)
          << "; BDF2 dt = 0.01: " << rounded(r2, 2)
          << ", dt = 0.005: " << rounded(r2h, 2) << std::endl;
  deallog << "BDF2 rebounds higher than BDF1: "
          << (r2 > r1 && r2h > r1h ? "yes" : "no") << std::endl;
  deallog << "a smaller step rebounds higher (BDF1, BDF2): "
          << (r1h > r1 ? "yes" : "no") << ", " << (r2h > r2 ? "yes" : "no")
          << std::endl;
  deallog << "BDF2 at dt = 0.005 keeps more than 70% of the height: "
          << (r2h > 0.7 ? "yes" : "no") << "; no rebound above the drop: "
          << (std::max({r1, r1h, r2, r2h}) < 1 ? "yes" : "no") << std::endl;
}
