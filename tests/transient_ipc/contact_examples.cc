// The shipped IPC contact examples (parameter_files/transient_ipc) do what
// doc/transient_ipc.md says, run as a user runs them (some shortened with
// --set): no pair ever touches (smallest distance > 0), no element inverts,
// and each shows its physics: the balls bounce, the block slides with
// a = g (sin 30 - mu cos 30), the thrown block passes its momentum on with
// the center of mass moving at constant velocity, the pressed stack's floor
// carries the load, balls roll on obstacle meshes (a Gmsh polyline, an OBJ
// surface), interlocking parts carry a pull, a thrown piece bounces among
// pegs, a thrown cube pushes another on a table, the pile settles.

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <cmath>

using nlohmann::json;

/// The common IPC findings of a run.
void
check_contact(const json &s)
{
  check("smallest distance positive",
        !s["ipc"]["min_distance"].is_null() &&
          s["ipc"]["min_distance"].get<double>() > 0);
  check("no inverted element", s["ipc"]["inverted_elements"].get<int>() == 0);
}

/// Vertical mean displacement of each step (last coordinate).
std::vector<double>
heights(const json &s)
{
  std::vector<double> y;
  for (const auto &step : s["steps"])
    y.push_back(step["mean_displacement"].back().get<double>());
  return y;
}

void
bounce(const std::string &name, const std::string &extra)
{
  const json s = run_example("transient_ipc", name, extra);
  check_contact(s);
  const auto         y   = heights(s);
  const unsigned int low = std::min_element(y.begin(), y.end()) - y.begin();
  check("falls, touches the floor and rises again",
        low > 0 && low + 1 < y.size() && y.back() > y[low] + 0.05);
  const double force = s["steps"][low]["contact"]["obstacle_force"].back();
  check("the floor pushes the ball up at its lowest point", force > 0);
}

int
main()
{
  initlog();
  bounce("ball_bounce_2d", " --set 'Time/End time=0.6'");
  bounce("ball_bounce_3d",
         " --set 'Time/End time=0.6' --set 'Mesh/Initial refinement=1'");

  {
    const json s = run_example("transient_ipc", "block_on_slope");
    check_contact(s);
    // x = x0 + v0 t + a t^2 / 2 over t >= 0.1 (after landing): a from
    // the second differences of equally spaced samples.
    std::vector<double> x;
    for (const auto &step : s["steps"])
      if (step["time"].get<double>() >= 0.1 - 1e-12)
        x.push_back(step["mean_displacement"][0].get<double>());
    double a = 0;
    for (unsigned int i = 1; i + 1 < x.size(); ++i)
      a += (x[i + 1] - 2 * x[i] + x[i - 1]) / (0.01 * 0.01);
    a /= x.size() - 2;
    const double exact = 9.81 * (0.5 - 0.2 * std::sqrt(3.) / 2);
    check("slides with a = g (sin 30 - 0.2 cos 30) within 1%",
          std::abs(a - exact) < 0.01 * exact);
  }
  {
    const json s = run_example("transient_ipc", "two_blocks_collision");
    check_contact(s);
    double worst = 0;
    for (const auto &step : s["steps"])
      if (step["time"].get<double>() > 0)
        worst = std::max(worst,
                         std::abs(step["mean_displacement"][0].get<double>() /
                                    step["time"].get<double>() -
                                  1.));
    check("center of mass moves at 1 (momentum conserved) to 1e-8",
          worst < 1e-8);
    const auto &p = s["steps"].back()["point_displacements"];
    check("the hit block has moved further than the thrown one after 0.6",
          p[1][0].get<double>() > p[0][0].get<double>());
  }
  {
    const json s = run_example("transient_ipc", "stack_press_3d");
    check_contact(s);
    const double f = s["steps"].back()["contact"]["obstacle_force"][2];
    check("floor reaction = load (10) to 1e-6", std::abs(f - 10.) < 1e-5);
  }
  {
    // Obstacle meshes: a Gmsh polyline ramp (2D), an OBJ bowl (3D).
    const json s = run_example("transient_ipc", "ball_on_ramp_2d");
    check_contact(s);
    check("the ball rolls down the ramp and 4 along the floor",
          s["steps"].back()["mean_displacement"][0].get<double>() > 4);
    const json b = run_example("transient_ipc", "ball_in_bowl_3d");
    check_contact(b);
    double least_x = 0;
    for (const auto &step : b["steps"])
      least_x = std::min(least_x, step["mean_displacement"][0].get<double>());
    check("the ball passes the bowl's axis (x = 1.2 -> below 0)",
          least_x < -1.2);
  }
  {
    const json s = run_example("transient_ipc", "interlock_static_2d");
    check_contact(s);
    check("the clamp carries the pull on the insert (20 x 0.59) to 1e-6",
          std::abs(s["reactions"]["1"][1].get<double>() + 11.8) < 1e-5);
  }
  {
    const json s = run_example("transient_ipc",
                               "puzzle_bounce_2d",
                               " --set 'Time/End time=1'");
    check_contact(s);
    unsigned int touching = 0;
    for (const auto &step : s["steps"])
      touching += step["contact"]["active_pairs"].get<int>() > 0 ? 1 : 0;
    check("the piece meets the pegs and walls", touching > 10);
  }
  {
    const json s =
      run_example("transient_ipc", "pool_3d", " --set 'Time/End time=0.5'");
    check_contact(s);
    const auto &p = s["steps"].back()["point_displacements"];
    check("the thrown cube has pushed the resting one on",
          p[1][0].get<double>() > 0.1);
  }
  {
    const json s =
      run_example("transient_ipc", "pile_2d", " --set 'Time/End time=1.2'");
    check_contact(s);
    check("many pairs in contact at the end",
          s["steps"].back()["contact"]["active_pairs"].get<int>() > 20);
  }
}
