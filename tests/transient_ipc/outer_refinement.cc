// Optimization/Outer step = refine on the shipped bridge (thesis Fig. 3.4):
// each of thesis Algorithm 1's outer iterations ends in a refinement of
// the mesh where the indicator of the current design is largest (Kelly's,
// then the goal estimate of the stress norm), and the next L-BFGS run goes
// on from the same design: the shape is carried over exactly, so J moves
// by the discretization error only. The quality guard checks the cells'
// corners, which refined cells would meet. A run stopped inside outer
// iteration 2 (as a killed one would be, at Max iterations = 6) resumes on
// the refined mesh, rebuilt from its file.

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <cmath>

namespace
{
  // The stress and volume terms of the file: its boundary smoothing term
  // sums over boundary edges, which a refinement splits.
  const std::string settings = " --set 'Objective/Terms=stress : p=2 ; "
                               "volume bound : bound=6.1425, weight=1e5'"
                               " --set 'Optimization/Outer iterations=3'"
                               " --set 'Optimization/Inner iterations=4'"
                               " --set 'Optimization/Outer step=refine'"
                               " --set 'Finite element/Adaptivity=h'";

  void
  check_run(const nlohmann::json &s, const std::string &indicator)
  {
    const auto &o = s["optimization"];
    const auto &r = o["remeshes"];
    check(indicator + ": 3 outer iterations, refined after 4 and 8",
          o["outer_iterations"] == 3 && r.size() == 2 &&
            r[0]["iteration"] == 4 && r[1]["iteration"] == 8 &&
            r[0]["refinement"] == true);
    check(indicator + ": DoFs 882 -> about 1.9x -> about 3.9x",
          r[0]["n_dofs"].get<double>() > 1.8 * 882 &&
            r[1]["n_dofs"].get<double>() > 1.8 * r[0]["n_dofs"].get<double>());
    bool close = true;
    for (const auto &x : r)
      close &= std::abs(x["objective_after"].get<double>() /
                          x["objective_before"].get<double>() -
                        1) < 0.01;
    check(indicator + ": J of the carried design within 1% on the finer mesh",
          close);
    check(indicator + ": J/J0 below 0.35", o["ratio"].get<double>() < 0.35);
    check(indicator + ": volume within 1%",
          std::abs(s["final_volume"].get<double>() / 6.1425 - 1) < 0.01);
  }
} // namespace

int
main()
{
  initlog();
  check_run(run_example("transient_ipc",
                        "bridge_stress",
                        settings + " --set 'Optimization/Max iterations=12'"),
            "kelly");
  check_run(run_example("transient_ipc",
                        "bridge_stress",
                        settings + " --set 'Optimization/Max iterations=12'"
                                   " --set 'Finite element/Error indicator="
                                   "goal'"),
            "goal");

  const auto killed =
    run_example("transient_ipc",
                "bridge_stress",
                settings + " --set 'Optimization/Max iterations=6'");
  const auto r =
    run_example("transient_ipc",
                "bridge_stress",
                settings + " --set 'Optimization/Max iterations=12'"
                           " --set 'Optimization/Resume=true'");
  const auto &ro = r["optimization"];
  check("resumed from iteration 6",
        read_file("bridge_stress.stdout").find("resuming from iteration 6") !=
          std::string::npos);
  check("resumed: the third outer iteration from iteration 8 on the "
        "twice-refined mesh (the refinement at 4 from the checkpoint)",
        ro["outer_iterations"] == 3 && ro["remeshes"].size() == 2 &&
          ro["remeshes"][0]["iteration"] == 4 &&
          ro["remeshes"][1]["iteration"] == 8 &&
          ro["remeshes"][1]["n_dofs"].get<double>() > 3.4 * 882);
  // The same mesh and design: the same J at the checkpoint's iteration.
  const double J6 = killed["optimization"]["final_objective"].get<double>();
  double       J  = 0;
  for (const auto &entry : r["history"])
    if (entry["iteration"] == 6)
      J = entry["objective"].get<double>();
  check("resumed: J at iteration 6 as the killed run's (to 1e-10)",
        std::abs(J / J6 - 1) < 1e-10);
  check("resumed: J/J0 below the killed run's",
        ro["ratio"].get<double>() <
          killed["optimization"]["ratio"].get<double>());
}
