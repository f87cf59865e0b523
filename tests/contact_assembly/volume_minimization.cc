// Thesis Table 2.2's "Post vol. min." (Optimization/Volume minimization
// iterations) on the shipped 2D connector: 6 iterations minimize the
// stress with the volume bounded, then 6 more minimize the volume with the
// stress held within 2% of the peak the first stage left. The volume
// falls, the peak stress stays near the first stage's, and a run stopped in
// the second stage resumes in it, with its objective.

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <cmath>

namespace
{
  const std::string settings = " --set 'Optimization/Remesh quality=0'"
                               " --set 'Optimization/Volume minimization "
                               "iterations=6'";

  double
  volume(const nlohmann::json &state)
  {
    return state["volume"].get<double>();
  }
} // namespace

int
main()
{
  initlog();
  const auto s =
    run_example("contact_assembly",
                "connector_stress",
                settings + " --set 'Optimization/Max iterations=6'");
  const auto &o     = s["optimization"];
  const auto &stage = o["volume_minimization"];
  check("the volume stage starts at iteration 6 and runs to 12",
        stage["iteration"] == 6 && o["iterations"] == 12);
  check("its terms: the volume and a bound on the stress",
        stage["terms"].get<std::string>().rfind("volume : weight=", 0) == 0 &&
          stage["terms"].get<std::string>().find("stress bound : bound=") !=
            std::string::npos);
  const double V1 = volume(stage["start_state"]), V2 = volume(o["final_state"]);
  const double S1 = stage["start_state"]["max_stress"].get<double>();
  const double S2 = o["final_state"]["max_stress"].get<double>();
  check("the volume falls by more than 2% in the stage", V2 < 0.98 * V1);
  check("the peak stress stays within 6% of the stage's start", S2 < 1.06 * S1);
  check("the stage is an outer iteration of its own",
        o["outer"].size() == 2 && o["outer"][1]["iteration"] == 6);

  // Stopped at iteration 9 (in the stage), resumed to 12.
  run_example("contact_assembly",
              "connector_stress",
              settings + " --set 'Optimization/Max iterations=6'" +
                " --set 'Optimization/Volume minimization iterations=3'");
  const auto r =
    run_example("contact_assembly",
                "connector_stress",
                settings + " --set 'Optimization/Max iterations=6'" +
                  " --set 'Optimization/Resume=true'");
  const auto &ro = r["optimization"];
  check("resumed from iteration 9 in the volume stage",
        read_file("connector_stress.stdout")
              .find("resuming from iteration 9") != std::string::npos &&
          ro["iterations"] == 12);
  // (The stage starts from the stress stage's design, which a resumed job
  // does not rebuild, so the L-BFGS memory restarts: close, not identical.)
  check("resumed: the volume falls by more than 2% in the stage",
        volume(ro["final_state"]) < 0.98 * V1);
}
