// Inverse design with forma-laminate: the target (E, nu) is the homogenized
// result of a known Hexagon structure that is not in the table, on the same
// grid, so it is reachable. The inverse mode, started from its own coarse
// table sweep and from a sweep's samples.csv, must reach it within the
// tolerance (misfit sqrt((E/E* - 1)^2 + (nu - nu*)^2) <= 1e-3).

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>

namespace
{
  const std::string base =
    "set Dimension = 2\n"
    "subsection Grid\n set Cells along height = 32\nend\n"
    "subsection Output\n set Write vtu = false\nend\n";
  const std::string sweep =
    "subsection Sweep\n set Families = hexagon, triangle\n"
    " set p1 = 0.7:0.9:3\n set p2 = 0, 1\n set p3 = 0.5\n"
    " set p4 = 0.5:0.9:3\nend\n";

  nlohmann::json
  summary(const std::string &directory)
  {
    return nlohmann::json::parse(read_file(directory + "/summary.json"));
  }

  void
  check(const std::string &name,
        const std::string &inverse_section,
        const double       E,
        const double       nu)
  {
    const int    code = run_app(FORMA_APP,
                             name,
                             base + sweep + "set Output directory = " + name +
                               "\nset Mode = inverse\nsubsection Inverse\n" +
                               inverse_section + "end\n");
    const auto   s    = summary(name);
    const double dE   = std::abs(s["result"]["E"].get<double>() / E - 1),
                 dn   = std::abs(s["result"]["nu"].get<double>() - nu);
    dealii::deallog << name << ": exit code " << code << ", reached "
                    << s["reached"].get<bool>() << ", |E/E* - 1| "
                    << (dE <= 1e-3 ? "<= 1e-3" : "LARGE") << ", |nu - nu*| "
                    << (dn <= 1e-3 ? "<= 1e-3" : "LARGE") << ", candidates "
                    << (s["candidates"].size() <= 3 ? "<= 3" : "MORE")
                    << std::endl;
  }
} // namespace

int
main()
{
  initlog();
  // The target: a structure between the table's samples.
  run_app(FORMA_APP,
          "target",
          base + "set Output directory = target\nset Mode = homogenize\n"
                 "subsection Structure\n set Type = hexagon\n set p1 = 0.83\n"
                 " set p2 = 0.4\n set p3 = 0.5\n set p4 = 0.62\nend\n");
  const auto   t  = summary("target");
  const double E  = t["result"]["E"].get<double>(),
               nu = t["result"]["nu"].get<double>();
  const std::string target =
    " set Target Young's modulus = " + std::to_string(E) +
    "\n set Target Poisson's ratio = " + std::to_string(nu) + "\n";

  check("own_table", target + " set Table cells along height = 16\n", E, nu);

  // A table from an earlier sweep.
  run_app(FORMA_APP,
          "table",
          "set Dimension = 2\nset Output directory = table\n"
          "set Mode = sweep\nsubsection Grid\n set Cells along height = 16\n"
          "end\n" +
            sweep);
  check("table_file", target + " set Table file = table/samples.csv\n", E, nu);

  // Thesis Table 5.1's run, short: the compliance misfit toward the HS
  // bound's (0.5, -0.5), with the shape derivative on a coarse P1 mesh at
  // every iterate.
  const int code = run_app(
    FORMA_APP,
    "table_5_1",
    base + "set Output directory = table_5_1\nset Mode = inverse\n"
           "subsection Base material\n set Poisson's ratio = 0\nend\n"
           "subsection Sweep\n set Families = hexagon\n set p1 = 0.8\n"
           " set p2 = 0.3\n set p3 = 0.5\n set p4 = 0.6\nend\n"
           "subsection Inverse\n set Target Young's modulus = 0.5\n"
           " set Target Poisson's ratio = -0.5\n set Objective = compliance\n"
           " set Candidates = 1\n set Max iterations = 3\n"
           " set Table cells along height = 16\n"
           " set Report shape derivative = true\nend\n"
           "subsection Conforming mesh\n set Element size = 0.05\n"
           " set Degree = 1\nend\n");
  const auto  s       = summary("table_5_1");
  const auto &rows    = s["shape_derivative"];
  bool        J_falls = true, positive = true, shares = true;
  for (unsigned int i = 0; i < rows.size(); ++i)
    {
      if (i > 0)
        J_falls = J_falls && rows[i]["J"] < rows[i - 1]["J"];
      positive = positive && rows[i]["shape_derivative_norm"] > 0 &&
                 rows[i]["interface_vertices"] > 0;
      shares =
        shares && rows[i]["corner_share"] >= 0 && rows[i]["corner_share"] <= 1;
    }
  dealii::deallog << "table_5_1: exit code " << code << ", rows " << rows.size()
                  << ", J falls " << J_falls
                  << ", shape derivative and interface nonzero " << positive
                  << ", corner shares in [0, 1] " << shares << std::endl;
}
