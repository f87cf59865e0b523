// A remesh that fails between outer iterations (thesis Algorithm 1) ends
// the outer loop; the run goes on on its mesh without the Inner iterations
// limit, to its own stagnation or Max iterations. The shipped bridge with
// boundary smoothing of weight 100 instead of 30: after the first outer
// iteration's 12 iterations, Gmsh's quads under the middle load have a
// cell below the quality guard. A run stopped after that failure resumes
// on its mesh without trying the remesh again.

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <fstream>
#include <iterator>

namespace
{
  const std::string settings =
    " --set 'Objective/Terms=stress : p=2 ; volume bound : bound=6.1425, "
    "weight=1e5 ; boundary smoothing : p=2, weight=100'";

  bool
  stdout_mentions(const std::string &name, const std::string &text)
  {
    std::ifstream     in(name + ".stdout");
    const std::string out((std::istreambuf_iterator<char>(in)),
                          std::istreambuf_iterator<char>());
    return out.find(text) != std::string::npos;
  }
} // namespace

int
main()
{
  initlog();
  const auto  s = run_example("transient_ipc", "bridge_stress", settings);
  const auto &o = s["optimization"];
  const auto &r = o["remeshes"];
  check("one remesh tried, after iteration 12, and it failed",
        r.size() == 1 && r[0]["iteration"] == 12 &&
          r[0]["description"].get<std::string>().find(
            "remeshing failed, continuing on the current mesh") == 0);
  check("the run went on past the 12 inner iterations, on its mesh",
        o["iterations"].get<unsigned int>() > 12 && o["outer_iterations"] == 1);
  check("it stopped by its own decrease, not by an iteration limit",
        o["stop_reason"].get<std::string>().find("relative decrease") == 0);

  run_example("transient_ipc",
              "bridge_stress",
              settings + " --set 'Optimization/Max iterations=13'");
  const auto resumed =
    run_example("transient_ipc",
                "bridge_stress",
                settings + " --set 'Optimization/Resume=true'");
  check("resumed from iteration 13",
        stdout_mentions("bridge_stress", "resuming from iteration 13"));
  // The summary keeps the failed remesh of the run before (from the
  // checkpoint), and only that one.
  const auto &rr = resumed["optimization"]["remeshes"];
  check("without trying the remesh again",
        !stdout_mentions("bridge_stress", "remesh") && rr.size() == 1 &&
          rr[0]["iteration"] == 12);
}
