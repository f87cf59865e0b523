// A block on an inclined plane with IPC contact and lagged friction
// (gravity tilted by theta = 30 degrees against a horizontal plane): with
// mu < tan(theta) it slides with a = g (sin(theta) - mu cos(theta)), with
// mu > tan(theta) it sticks (creeps slower than the friction smoothing's
// velocity eps_v: the static regime of IPC friction). The
// plane's reaction balances the weight's normal component, the distance
// stays positive and no element inverts.

#include "ipc_tests.h"

#include <cmath>

using namespace dealii;

void
run(const double mu)
{
  const double theta = M_PI / 6, g = 9.81;
  auto         sim = make_ipc_simulator<2>(
    "subsection Mesh\n set Generator = subdivided_hyper_rectangle\n"
            " set Generator arguments = 4, 2 : 0, 0.0005 : 1, 0.5005 : false\nend\n"
            "subsection Finite element\n set Degree = 1\nend\n"
            "subsection Material\n set Model = neo-hookean\n"
            " set Bodies = * : E = 1e8, nu = 0.3, density = 1000\nend\n"
            "subsection Loads\n set Gravity = " +
    std::to_string(g * std::sin(theta)) + ", " +
    std::to_string(-g * std::cos(theta)) +
    "\nend\n"
            "subsection Time\n set Problem = transient\n set End time = 0.4\n"
            " set Time step = 0.01\n set BDF order = 2\nend\n"
            "subsection IPC\n set Enabled = true\n set Barrier distance = 1e-3\n"
            " set Obstacles = plane : 0, 0 : 0, 1\n"
            " set Friction coefficient = " +
    std::to_string(mu) + "\nend\n");
  sim.run();
  std::vector<double> t, x;
  double              min_distance = 1, normal_force = 0;
  unsigned int        inverted = 0;
  for (const auto &s : sim.steps())
    {
      if (s.step == 0)
        continue;
      if (s.time >= 0.1 - 1e-12)
        {
          t.push_back(s.time);
          x.push_back(s.mean_displacement[0]);
        }
      if (!s.contact["min_distance"].is_null())
        min_distance =
          std::min(min_distance, double(s.contact["min_distance"]));
      inverted += int(s.contact["inverted_elements"]);
      if (s.time >= 0.1 - 1e-12)
        normal_force += double(s.contact["obstacle_force"][1]) / 31.;
    }
  const double weight_normal = 1000 * 0.5 * g * std::cos(theta);
  deallog << "mu = " << mu << ": ";
  if (mu < std::tan(theta))
    {
      const double a     = fitted_acceleration(t, x);
      const double exact = g * (std::sin(theta) - mu * std::cos(theta));
      deallog << "sliding, a = " << rounded(a, 3) << " (exact "
              << rounded(exact, 3) << "), relative error below 1%: "
              << (std::abs(a - exact) < 0.01 * exact ? "yes" : "no");
    }
  else
    {
      // Once friction has caught the block (its first contact steps slide:
      // the normal force is lagged), it creeps only by the smoothing.
      // The static regime of the smoothed friction: slip per step below
      // eta = eps_v dt, i.e. a creep speed below eps_v (1e-3).
      const double speed = (x.back() - x[t.size() / 3]) / 0.2;
      deallog << "sticks, creep speed from t = 0.2 to 0.4 between 0.1 and 1 "
                 "eps_v: "
              << (std::abs(speed) < 1e-3 && std::abs(speed) > 1e-4 ? "yes" :
                                                                     "no");
    }
  deallog << "; plane reaction / weight normal component = "
          << rounded(normal_force / weight_normal, 3)
          << "; distance stayed positive: " << (min_distance > 0 ? "yes" : "no")
          << ", inverted elements: " << inverted << std::endl;
}

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  run(0.);
  run(0.2);
  run(0.8);
}
