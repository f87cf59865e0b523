// The shipped coat hooks of forma-contact-assembly (parameter_files/
// contact_assembly/hook*.prm, thesis Fig. 2.20), 30 iterations each: held by
// contact alone, both get stronger with the volume held, and the
// disassembly term of hook_disassembly falls well below its start.

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
    const std::string short_run = " --set 'Optimization/Max iterations=30'";
    const auto        a = run_example("contact_assembly", "hook", short_run);
    const auto        b =
      run_example("contact_assembly", "hook_disassembly", short_run);
    for (const auto *s : {&a, &b})
      {
        check("max stress below 0.8 of its start",
              (*s)["final_max_stress"].get<double>() <
                0.8 * (*s)["initial_max_stress"].get<double>());
        check("volume within 2% of its start",
              std::abs((*s)["final_volume"].get<double>() /
                         (*s)["initial_volume"].get<double>() -
                       1) < 0.02);
      }
    const auto &h = b["history"];
    check("disassembly term below 0.5 of its start",
          h.back()["terms"]["disassembly"].get<double>() <
            0.5 * h.front()["terms"]["disassembly"].get<double>());
  }
}
