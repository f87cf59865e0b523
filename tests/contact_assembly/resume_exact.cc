// Kill-and-resume gives the uninterrupted run (issue 44). The checkpoint
// keeps the L-BFGS memory, the objective's scale and the job's first
// gradient norm, so the shipped connector stopped after iteration 6 (the
// third on its mesh after three remeshes) and resumed takes the same steps
// as the run that went on: iterations 7 and 8, the final stresses, volume
// and relative gradient norm agree to 1e-12, and the resumed summary holds
// the whole history (the checkpoint keeps the job's records). Resumed from the
// same checkpoint without the memory (as older checkpoints were), the steps
// differ: the comparison can fail.

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>

namespace
{
  // J by iteration, for the iterations both summaries have.
  double
  largest_difference(const nlohmann::json &a, const nlohmann::json &b)
  {
    double largest = 0;
    for (const auto &x : a["history"])
      for (const auto &y : b["history"])
        if (x["iteration"] == y["iteration"])
          largest = std::max(largest,
                             std::abs(x["objective"].get<double>() -
                                      y["objective"].get<double>()) /
                               std::abs(x["objective"].get<double>()));
    for (const std::string key : {"final_max_stress", "final_volume"})
      largest = std::max(largest,
                         std::abs(a[key].get<double>() - b[key].get<double>()) /
                           std::abs(a[key].get<double>()));
    const double ga = a["optimization"]["relative_gradient_norm"],
                 gb = b["optimization"]["relative_gradient_norm"];
    return std::max(largest, std::abs(ga - gb) / ga);
  }

  // The summary's records of the iterations before the checkpoint: the
  // history (iterations, their restart marks, objectives), the remeshes
  // and the outer iterations, as the uninterrupted run reports them.
  bool
  same_records(const nlohmann::json &a, const nlohmann::json &b)
  {
    const auto &ha = a["history"], &hb = b["history"];
    if (ha.size() != hb.size())
      return false;
    for (unsigned int i = 0; i < ha.size(); ++i)
      if (ha[i]["iteration"] != hb[i]["iteration"] ||
          ha[i].contains("remeshed") != hb[i].contains("remeshed") ||
          std::abs(ha[i]["objective"].get<double>() -
                   hb[i]["objective"].get<double>()) >
            1e-12 * std::abs(ha[i]["objective"].get<double>()))
        return false;
    const auto &oa = a["optimization"], &ob = b["optimization"];
    if (oa["remeshes"].size() != ob["remeshes"].size() ||
        oa["outer"].size() != ob["outer"].size())
      return false;
    for (unsigned int i = 0; i < oa["remeshes"].size(); ++i)
      if (oa["remeshes"][i]["iteration"] != ob["remeshes"][i]["iteration"])
        return false;
    for (unsigned int i = 0; i < oa["outer"].size(); ++i)
      if (oa["outer"][i]["iteration"] != ob["outer"][i]["iteration"] ||
          std::abs(oa["outer"][i]["reduction_percent"].get<double>() -
                   ob["outer"][i]["reduction_percent"].get<double>()) > 1e-9)
        return false;
    return true;
  }
} // namespace

int
main()
{
  initlog();
  namespace fs            = std::filesystem;
  const std::string name  = "connector_stress";
  const std::string until = " --set 'Optimization/Max iterations=";
  const auto        whole = run_example("contact_assembly", name, until + "8'");

  run_example("contact_assembly", name, until + "6'");
  const std::string checkpoint = name + "/optimization.checkpoint.json";
  fs::copy_file(checkpoint,
                "checkpoint_6.json",
                fs::copy_options::overwrite_existing);
  const auto resumed =
    run_example("contact_assembly",
                name,
                until + "8' --set 'Optimization/Resume=true'");
  check("resumed from iteration 6",
        read_file(name + ".stdout").find("resuming from iteration 6") !=
          std::string::npos);
  check("resumed run ends at iteration 8",
        resumed["optimization"]["iterations"] == 8);
  check("iterations 6-8, stresses, volume, gradient norm as uninterrupted "
        "(1e-12)",
        largest_difference(whole, resumed) < 1e-12);
  check("its summary's history, remeshes and outer iterations from 0 on are "
        "the uninterrupted run's",
        same_records(whole, resumed));

  nlohmann::json c;
  std::ifstream("checkpoint_6.json") >> c;
  c.erase("lbfgs");
  std::ofstream(checkpoint) << c.dump();
  const auto forgetful =
    run_example("contact_assembly",
                name,
                until + "8' --set 'Optimization/Resume=true'");
  check("without the L-BFGS memory the resumed steps differ (above 1e-6)",
        largest_difference(whole, forgetful) > 1e-6);
}
