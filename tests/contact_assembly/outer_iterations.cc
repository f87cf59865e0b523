// Thesis Algorithm 1's outer loop (Optimization/Outer iterations) on the
// shipped connector: each inner L-BFGS run of at most 4 iterations is
// followed by a remesh and a fresh run, 3 runs in all, and the volume
// bound's weight ramps linearly from 100 to 300 over them ('final
// weight', thesis Table 2.2's "a/b"). summary.json reports every outer
// iteration with its weights. A run killed inside an outer iteration
// resumes in it.

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <cmath>

int
main()
{
  initlog();
  const auto  s     = run_example("contact_assembly",
                             "connector_stress",
                             " --set 'Optimization/Max iterations=12'"
                                  " --set 'Optimization/Outer iterations=3'"
                                  " --set 'Optimization/Inner iterations=4'"
                                  " --set 'Optimization/Remesh quality=0'"
                                  " --set 'Objective/Terms=stress : p=20 ; volume "
                                  "bound : bound=4, weight=100, final weight=300'");
  const auto &o     = s["optimization"];
  const auto &outer = o["outer"];
  check("3 outer iterations of 3",
        o["outer_iterations"] == 3 && o["max_outer_iterations"] == 3 &&
          outer.size() == 3);
  check("2 remeshes, after iterations 4 and 8",
        o["remeshes"].size() == 2 && outer[1]["iteration"] == 4 &&
          outer[2]["iteration"] == 8);
  for (unsigned int i = 0; i < outer.size(); ++i)
    check("outer iteration " + std::to_string(i + 1) +
            ": volume bound weight " + std::to_string(100 * (i + 1)),
          std::abs(outer[i]["weights"]["volume bound"].get<double>() -
                   100. * (i + 1)) < 1e-12);
  check("the last outer iteration's reduction is the reported one",
        std::abs(outer[2]["reduction_percent"].get<double>() -
                 o["last_outer_reduction_percent"].get<double>()) < 1e-12);
  check("12 iterations in all", o["iterations"] == 12);
  check("J/J0 below 0.5", o["ratio"].get<double>() < 0.5);
  check("max stress below 0.5 of the initial",
        s["final_max_stress"].get<double>() <
          0.5 * s["initial_max_stress"].get<double>());
  check("volume within 2%",
        std::abs(s["final_volume"].get<double>() / 4. - 1) < 0.02);

  // Kill-and-resume inside outer iteration 2: the checkpoint keeps the
  // outer iteration and where it started, so the resumed run remeshes
  // after iteration 8 and ends in outer iteration 3 with weight 300.
  const std::string settings =
    " --set 'Optimization/Outer iterations=3'"
    " --set 'Optimization/Inner iterations=4'"
    " --set 'Optimization/Remesh quality=0'"
    " --set 'Objective/Terms=stress : p=20 ; volume bound : bound=4, "
    "weight=100, final weight=300'";
  run_example("contact_assembly",
              "connector_stress",
              settings + " --set 'Optimization/Max iterations=6'");
  const auto r =
    run_example("contact_assembly",
                "connector_stress",
                settings + " --set 'Optimization/Max iterations=12'"
                           " --set 'Optimization/Resume=true'");
  const auto &ro = r["optimization"];
  check("resumed from iteration 6",
        read_file("connector_stress.stdout")
            .find("resuming from iteration 6") != std::string::npos);
  // The checkpoint keeps the outer iterations before it: the resumed
  // summary lists all three.
  check("resumed: 3 outer iterations, from iterations 0, 4 and 8",
        ro["outer_iterations"] == 3 && ro["outer"].size() == 3 &&
          ro["outer"][0]["iteration"] == 0 &&
          ro["outer"][1]["iteration"] == 4 && ro["outer"][2]["iteration"] == 8);
  check("resumed: weights 100, 200 and 300",
        ro["outer"][0]["weights"]["volume bound"] == 100. &&
          ro["outer"][1]["weights"]["volume bound"] == 200. &&
          ro["outer"][2]["weights"]["volume bound"] == 300.);
  check("resumed: 12 iterations, J/J0 below 0.5",
        ro["iterations"] == 12 && ro["ratio"].get<double>() < 0.5);
}
