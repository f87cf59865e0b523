// Two elastic blocks, the left one thrown at the right one, frictionless
// and undamped, no gravity (IPC contact between bodies): the total momentum
// (mass-weighted mean velocity) is conserved through the impact to
// round-off, momentum passes to the hit block, the distance stays positive
// and no element inverts. In 3D a stack of three blocks pressed onto a
// plane (static, IPC between the blocks and with the plane): the plane's
// reaction equals the applied load. The same on two ranks (the collision
// mesh gathered from both, candidate pairs split between them).

#include "ipc_tests.h"

#include <cmath>

using namespace dealii;

void
collision()
{
  auto sim = make_ipc_simulator<2>(
    "subsection Mesh\n set Source = file\n"
    " set File = ../../parameter_files/transient_ipc/meshes/two_blocks_2d.msh\nend\n"
    "subsection Material\n set Model = neo-hookean\n"
    " set Bodies = * : E = 1e4, nu = 0.3, density = 1\nend\n"
    "subsection Initial conditions\n set Velocity = if(x < 1.05, 2, 0), 0\nend\n"
    "subsection Time\n set Problem = transient\n set End time = 0.4\n"
    " set Time step = 0.005\n set BDF order = 2\nend\n"
    "subsection IPC\n set Enabled = true\nend\n"
    "subsection Output\n set Points = 0.5, 0.5 ; 1.6, 0.7\nend\n");
  sim.run();
  // Equal masses: the center of mass moves at 1.
  double       worst = 0, min_distance = 1;
  unsigned int inverted = 0, contact_steps = 0;
  for (const auto &s : sim.steps())
    {
      if (s.step == 0)
        continue;
      worst = std::max(worst, std::abs(s.mean_displacement[0] / s.time - 1.));
      worst = std::max(worst, std::abs(s.mean_displacement[1] / s.time));
      if (!s.contact["min_distance"].is_null())
        min_distance =
          std::min(min_distance, double(s.contact["min_distance"]));
      inverted += int(s.contact["inverted_elements"]);
      contact_steps += int(s.contact["active_pairs"]) > 0 ? 1 : 0;
    }
  const auto &steps = sim.steps();
  const auto &a     = steps.back().point_displacements,
             &b     = steps[steps.size() - 11].point_displacements;
  const double dt   = 10 * 0.005;
  const double v0 = (a[0][0] - b[0][0]) / dt, v1 = (a[1][0] - b[1][0]) / dt;
  deallog << "2D collision: steps in contact "
          << (contact_steps > 0 ? "> 0" : "0")
          << ", center of mass velocity (1, 0) to 1e-8: "
          << (worst < 1e-8 ? "yes" : "no")
          << "; after the impact the thrown block is slower than the hit one: "
          << (v0 < v1 ? "yes" : "no") << ", v0 + v1 = " << rounded(v0 + v1, 2)
          << "; distance stayed positive: " << (min_distance > 0 ? "yes" : "no")
          << ", inverted elements: " << inverted << std::endl;
}

void
press()
{
  auto sim = make_ipc_simulator<3>(
    "subsection Mesh\n set Source = file\n"
    " set File = ../../parameter_files/transient_ipc/meshes/stack_3d.msh\nend\n"
    "subsection Material\n set Model = neo-hookean\n"
    " set Bodies = * : E = 1000, nu = 0.3\nend\n"
    "subsection Boundary conditions\n"
    // Rollers on the left and front sides of each block; pressure on top.
    " set Dirichlet = 0 : x : 0 ; 10 : x : 0 ; 20 : x : 0 ; 4 : y : 0 ; "
    "14 : y : 0 ; 24 : y : 0\n"
    " set Traction = 25 : 0, 0, -10*t\nend\n"
    "subsection Time\n set Load steps = 2\nend\n"
    "subsection IPC\n set Enabled = true\n set Barrier distance = 0.01\n"
    " set Obstacles = plane : 0, 0, -0.005 : 0, 0, 1\nend\n");
  sim.run();
  const auto &s = sim.steps().back();
  deallog << "3D press: plane reaction z / load = "
          << rounded(double(s.contact["obstacle_force"][2]) / 10., 6)
          << ", active pairs > 0: "
          << (int(s.contact["active_pairs"]) > 0 ? "yes" : "no")
          << ", distance positive: "
          << (double(s.contact["min_distance"]) > 0 ? "yes" : "no")
          << ", inverted elements: " << int(s.contact["inverted_elements"])
          << std::endl;
}

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    initlog();
  collision();
  press();
}
