// Optimizing only some parts of an assembly (thesis Fig. 2.12, right):
// the shipped connector with Design/Fixed bodies = 2 keeps its cap as
// meshed (the cap's volume does not change, to round-off) while the base
// takes shape and its stress falls; an unknown material id is an error.

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>

int
main()
{
  initlog();
  const auto  s      = run_example("contact_assembly",
                             "connector_stress",
                             " --set 'Design/Fixed bodies=2'"
                                   " --set 'Optimization/Max iterations=15'");
  const auto &v0     = s["optimization"]["initial_state"]["volume_by_material"];
  const auto &v1     = s["optimization"]["final_state"]["volume_by_material"];
  const auto  change = [&](const std::string &id) {
    return std::abs(v1[id].get<double>() / v0[id].get<double>() - 1);
  };
  check("the cap's volume unchanged within 1e-10", change("2") < 1e-10);
  check("the base's volume changed by more than 1e-5", change("1") > 1e-5);
  // The thesis's "drastic effect of fixing only one part": the base's
  // peak falls, but the cap's own corners, which cannot change, keep the
  // assembly's maximum near where it was.
  const auto &m0 = s["optimization"]["initial_state"]["max_stress_by_material"];
  const auto &m1 = s["optimization"]["final_state"]["max_stress_by_material"];
  check("the base's max stress below 0.95 of its start",
        m1["1"].get<double>() < 0.95 * m0["1"].get<double>());
  check("the cap's max stress within 2% of its start",
        std::abs(m1["2"].get<double>() / m0["2"].get<double>() - 1) < 0.02);
  check("the assembly's max stress above 0.8 of its start (the fixed cap)",
        s["final_max_stress"].get<double>() >
          0.8 * s["initial_max_stress"].get<double>());
  // A material id the mesh does not have.
  const int code =
    std::system((std::string(FORMA_APP) + " " + FORMA_SOURCE_DIR +
                 "/parameter_files/contact_assembly/connector_stress.prm"
                 " --set 'Output directory=unknown_body'"
                 " --set 'Design/Fixed bodies=7' > unknown_body.stdout"
                 " 2> unknown_body.stderr")
                  .c_str());
  std::string message = read_file("unknown_body.stderr");
  while (!message.empty() && message.back() == '\n')
    message.pop_back();
  dealii::deallog << "unknown body: exit code non-zero: "
                  << (code != 0 ? "yes" : "no") << std::endl
                  << "  message: " << message << std::endl;
}
