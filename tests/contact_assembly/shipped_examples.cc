// The shipped forma-contact-assembly examples (parameter_files/
// contact_assembly) run as a user runs them and reach what
// doc/contact_assembly.md states: the box matches its closed form, the
// connector's stress falls with its volume held (a shortened run of the
// baseline, 40 iterations); the disassembly example's terms move as
// designed (10 iterations); the two-part lever's stress falls (20 iterations)
// and the bridge's (10); the tower crane's ESO-like step removes cells
// and the run goes on with the holes (its shape stage cut to 5
// iterations); the 3D stool stands on the floor and its connector's
// stress falls (6 iterations); the tent made from its graph stands on the
// floor and its stress falls (4 iterations), and so does the tent with an
// id per socket and the assembly term (2); the coat rack's hook connector
// hangs on its dowel and its stress falls (4 iterations). The hooks are in
// shipped_hooks.

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>

using nlohmann::json;


int
main()
{
  initlog();
  {
    const auto s   = run_example("contact_assembly", "box_on_floor");
    const auto top = s["steps"].back()["point_displacements"][0];
    check("u(2, 1) = (0.0078, -0.00911) within 1e-10",
          std::abs(top[0].get<double>() - 0.0078) < 1e-10 &&
            std::abs(top[1].get<double>() + 0.00911) < 1e-10);
    const auto f = s["contact"][0]["force"];
    check("the floor carries the load (0, 0.02) within 1e-12",
          std::abs(f[0].get<double>()) < 1e-12 &&
            std::abs(f[1].get<double>() - 0.02) < 1e-12);
  }
  // A shortened optimization lowers the max stress below `bound` of its
  // start with the volume held within 1%.
  const auto stress_falls = [](const std::string &name,
                               const unsigned int iterations,
                               const double       bound) {
    const auto   s      = run_example("contact_assembly",
                               name,
                               " --set 'Optimization/Max iterations=" +
                                 std::to_string(iterations) + "'");
    const double stress = s["final_max_stress"].get<double>() /
                          s["initial_max_stress"].get<double>();
    const double volume =
      s["final_volume"].get<double>() / s["initial_volume"].get<double>();
    check("max stress below " + std::to_string(bound).substr(0, 3) +
            " of its start",
          stress < bound);
    check("volume within 1% of its start", std::abs(volume - 1) < 0.01);
  };
  stress_falls("connector_stress", 40, 0.3);
  check("VTU of every iteration, convergence.png",
        std::ifstream("connector_stress/solution.pvd").good() &&
          std::ifstream("connector_stress/convergence.png").good());
  {
    // Only the joint designed: the disassembly term falls, the assembly
    // term keeps the slot free of undercuts, the volume cannot change.
    const auto  s     = run_example("contact_assembly",
                               "connector_disassembly",
                               " --set 'Optimization/Max iterations=10'");
    const auto &first = s["history"].front()["terms"];
    const auto &last  = s["history"].back()["terms"];
    check("disassembly term below 0.4 of its start",
          last["disassembly"].get<double>() <
            0.4 * first["disassembly"].get<double>());
    check("assembly term (weight 1e4) below 1e-4 unweighted",
          last["assembly"].get<double>() < 1e4 * 1e-4);
    check("volume unchanged within 1e-8",
          std::abs(s["final_volume"].get<double>() -
                   s["initial_volume"].get<double>()) < 1e-8);
  }
  stress_falls("lever", 20, 0.5);
  stress_falls("bridge", 10, 0.8);
  {
    const auto s       = run_example("contact_assembly",
                               "tower_crane",
                               " --set 'Optimization/Max iterations=5'");
    bool       removed = false;
    for (const auto &r : s["optimization"]["remeshes"])
      removed = removed || r.value("element_removal", false);
    const double volume =
      s["final_volume"].get<double>() / s["initial_volume"].get<double>();
    check("low-stress cells removed", removed);
    check("volume between 0.7 and 0.9 of its start",
          volume > 0.7 && volume < 0.9);
  }
  {
    // The 3D stool quarter, held by contact alone: the floor carries the
    // seat's load, its friction the legs' outward push (which the mirror
    // planes balance), and the connector's peak falls with its volume held.
    const auto  s     = run_example("contact_assembly",
                               "stool_3d",
                               " --set 'Optimization/Max iterations=6'");
    const auto &o     = s["optimization"];
    const auto &floor = o["initial_state"]["contact"][0];
    const auto &f     = floor["force"];
    check("floor contact (boundary 1) carries the load 6.25 within 1e-8",
          floor["boundary"].get<int>() == 1 &&
            std::abs(f[2].get<double>() - 6.25) < 1e-8);
    check("floor friction below mu = 0.4 times the normal force",
          std::hypot(f[0].get<double>(), f[1].get<double>()) <
            0.4 * f[2].get<double>());
    const auto peak = [&](const char *state) {
      return o[state]["max_stress_by_material"]["1"].get<double>();
    };
    check("connector's max stress below 0.8 of its start",
          peak("final_state") < 0.8 * peak("initial_state"));
    check("connector's volume within 1%",
          std::abs(
            o["final_state"]["volume_by_material"]["1"].get<double>() /
              o["initial_state"]["volume_by_material"]["1"].get<double>() -
            1) < 0.01);
  }
  double tent_peak = 0;
  {
    // The tent made from its graph (5 balls, 8 pipes): the floor carries
    // the load on the top ball's pad (a 10-gon in a circle of radius
    // sqrt(0.75^2 - 0.55^2), unit traction), friction holds nothing
    // sideways, and the peak falls with the volume held.
    const auto   s     = run_example("contact_assembly",
                               "tent_3d",
                               " --set 'Optimization/Max iterations=4'");
    const auto  &o     = s["optimization"];
    const auto  &floor = o["initial_state"]["contact"][0];
    const auto  &f     = floor["force"];
    const double disk  = M_PI * (0.75 * 0.75 - 0.55 * 0.55);
    const double gon   = disk * 10 * std::sin(M_PI / 5) / (2 * M_PI);
    check("floor (boundary 5) carries the pad's load: between the 10-gon's "
          "and the circle's area",
          floor["boundary"].get<int>() == 5 &&
            f[2].get<double>() > gon * (1 - 1e-9) && f[2].get<double>() < disk);
    check("floor's sideways force below 1e-8 of the load",
          std::hypot(f[0].get<double>(), f[1].get<double>()) <
            1e-8 * f[2].get<double>());
    check("max stress below 0.8 of its start",
          s["final_max_stress"].get<double>() <
            0.8 * s["initial_max_stress"].get<double>());
    check("volume within 1% of its start",
          std::abs(s["final_volume"].get<double>() /
                     s["initial_volume"].get<double>() -
                   1) < 0.01);
    tent_peak = s["initial_max_stress"].get<double>();
  }
  {
    // The same tent with a material per ball and per pipe, so an id per
    // socket (16 contacts), and the assembly term on each: the same mesh
    // and physics, so the same start.
    const auto s = run_example("contact_assembly",
                               "tent_sockets_3d",
                               " --set 'Optimization/Max iterations=2'");
    check("16 socket contacts and the floor",
          s["optimization"]["initial_state"]["contact"].size() == 17);
    check("initial max stress equals tent_3d's within 1e-8",
          std::abs(s["initial_max_stress"].get<double>() / tent_peak - 1) <
            1e-8);
    check("max stress below 0.9 of its start",
          s["final_max_stress"].get<double>() <
            0.9 * s["initial_max_stress"].get<double>());
  }
  {
    // The coat rack's hook connector: the three arms' tips (10-gons in
    // circles of radius 0.15, unit traction down) hang on the sockets,
    // which pass the load to the clamped dowel.
    const auto   s    = run_example("contact_assembly",
                               "coat_rack_hooks_3d",
                               " --set 'Optimization/Max iterations=4'");
    const auto  &o    = s["optimization"];
    const auto  &f    = o["initial_state"]["contact"][0]["force"];
    const double disk = 3 * M_PI * 0.15 * 0.15;
    const double gon  = disk * 10 * std::sin(M_PI / 5) / (2 * M_PI);
    check("sockets (boundary 10) carry the tips' load: between three "
          "10-gons' and circles' area",
          f[2].get<double>() > gon * (1 - 1e-9) && f[2].get<double>() < disk);
    check("sockets' sideways force below 1e-8 of the load",
          std::hypot(f[0].get<double>(), f[1].get<double>()) <
            1e-8 * f[2].get<double>());
    const auto peak = [&](const char *state) {
      return o[state]["max_stress_by_material"]["1"].get<double>();
    };
    check("connector's max stress below 0.9 of its start",
          peak("final_state") < 0.9 * peak("initial_state"));
  }
}
