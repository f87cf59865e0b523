// Optimization/Hold blocked vertices on the 3D stool joint (P1 tets, DD
// contact with friction): without it the mesh-quality guard rejects every
// trial step at one cell of the connector and the run stops early on a
// plateau (J/J0 0.75 from iteration 7 on); with it the vertices of the
// blocking cells are held, the rest of the shape goes on and J falls
// further, the connector's volume held.

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <cmath>

int
main()
{
  initlog();
  const std::string common = " --set 'Optimization/Max iterations=15'";
  const auto        stuck  = run_example("contact_assembly",
                                 "stool_joint_3d",
                                 common + " --set 'Optimization/Hold blocked "
                                                  "vertices=false'");
  const auto        ratio  = [](const nlohmann::json &s) {
    return s["final_objective"].get<double>() /
           s["initial_objective"].get<double>();
  };
  check("without holds: stops before 15 iterations",
        stuck["optimization"]["iterations"].get<unsigned int>() < 15);
  check("without holds: J/J0 above 0.74", ratio(stuck) > 0.74);

  const auto  s     = run_example("contact_assembly",
                             "stool_joint_3d",
                             common + " --set 'Optimization/Hold blocked "
                                           "vertices=true'");
  const auto &holds = s["optimization"]["holds"];
  check("vertices held, first after iteration 5",
        !holds.empty() && holds[0]["iteration"].get<unsigned int>() >= 5);
  check("with holds: runs all 15 iterations",
        s["optimization"]["iterations"].get<unsigned int>() == 15);
  check("with holds: J/J0 below 0.71", ratio(s) < 0.71);
  const auto &o              = s["optimization"];
  const auto  connector_peak = [](const nlohmann::json &s) {
    return s["optimization"]["final_state"]["max_stress_by_material"]["1"]
      .get<double>();
  };
  check("the connector's max stress below 0.97 of the run without holds",
        connector_peak(s) < 0.97 * connector_peak(stuck));
  check("the connector's volume within 1%",
        std::abs(o["final_state"]["volume_by_material"]["1"].get<double>() /
                   o["initial_state"]["volume_by_material"]["1"].get<double>() -
                 1) < 0.01);
}
