// IPC under stress (issue 44): the pile scenes, many elastic bodies
// thrown into a box with friction, in 2D (16 blocks) and 3D (27 cubes, at
// up to 6 m/s), on one rank and on two. Every run keeps every pair apart
// at every step (the smallest distance over the run is positive) and
// inverts no element, with many pairs in contact; two ranks give what one
// gives (the bodies' mean displacement at every step to 1e-6; the Newton
// iterations, which round-off near the tolerance can change by one here
// and there, to 2% in all).

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>

using nlohmann::json;

namespace
{
  json
  run_scene(const std::string &name,
            const unsigned int ranks,
            const std::string &end_time)
  {
    const std::string dir = name + "_np" + std::to_string(ranks);
    const std::string prm = std::string(FORMA_SOURCE_DIR) +
                            "/parameter_files/transient_ipc/" + name + ".prm";
    // Run as root (CI), Open MPI wants to be told; a machine with one
    // slot runs the two ranks on it.
    const std::string launcher =
      ranks > 1 ?
        "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
        "OMPI_MCA_rmaps_base_oversubscribe=1 timeout 600 " +
          std::string(FORMA_MPIEXEC) + " -np " + std::to_string(ranks) + " " :
        std::string();
    const int status = std::system(
      (launcher + FORMA_APP + " " + prm + " --set 'Output directory=" + dir +
       "'" + " --set 'Time/End time=" + end_time + "'" +
       " --set 'Output/Write vtu=false' > " + dir + ".stdout 2>&1")
        .c_str());
    json          s;
    std::ifstream in(dir + "/summary.json");
    if (in)
      in >> s;
    dealii::deallog << dir << ": exit code " << WEXITSTATUS(status)
                    << ", status "
                    << (s.contains("status") ? s["status"].get<std::string>() :
                                               std::string("(no summary)"))
                    << std::endl;
    return s;
  }

  // The largest difference in the bodies' mean displacement over the
  // steps, and whether the Newton iterations agree to 2% in all.
  std::pair<double, bool>
  compare(const json &a, const json &b)
  {
    if (a["steps"].size() != b["steps"].size())
      return {1e30, false};
    double largest = 0, na = 0, nb = 0;
    for (unsigned int i = 0; i < a["steps"].size(); ++i)
      {
        const auto &x = a["steps"][i], &y = b["steps"][i];
        na += x["newton_iterations"].get<double>();
        nb += y["newton_iterations"].get<double>();
        for (unsigned int d = 0; d < x["mean_displacement"].size(); ++d)
          largest = std::max(largest,
                             std::abs(x["mean_displacement"][d].get<double>() -
                                      y["mean_displacement"][d].get<double>()));
      }
    return {largest, std::abs(na - nb) <= 0.02 * na};
  }

  void
  scene(const std::string &name,
        const std::string &end_time,
        const int          contact_pairs)
  {
    json s[2];
    for (unsigned int r = 1; r <= 2; ++r)
      {
        s[r - 1] = run_scene(name, r, end_time);
        if (!s[r - 1].contains("steps"))
          return;
        check("smallest distance positive",
              !s[r - 1]["ipc"]["min_distance"].is_null() &&
                s[r - 1]["ipc"]["min_distance"].get<double>() > 0);
        check("no inverted element",
              s[r - 1]["ipc"]["inverted_elements"].get<int>() == 0);
        check("more than " + std::to_string(contact_pairs) +
                " pairs in contact at the end",
              s[r - 1]["steps"].back()["contact"]["active_pairs"].get<int>() >
                contact_pairs);
      }
    const auto [difference, same_iterations] = compare(s[0], s[1]);
    check("two ranks: the same Newton iterations in all (2%)", same_iterations);
    check("two ranks: the same mean displacements (1e-6)", difference < 1e-6);
  }
} // namespace

int
main()
{
  initlog();
  scene("pile_2d", "1.2", 20);
  scene("pile_3d", "0.4", 50);
}
