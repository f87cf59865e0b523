// The thesis's initial material-to-geometry map (ch. 4.6.2) end to end on a
// coarse mesh: H is linearized on V' (p1, p2, p5 fixed), V found
// transversal to its level sets, H' sampled on a 4^4 grid over V and
// inverted by simplices at 11 x 11 isotropic targets. The structures the
// simplex interpolation gives are checked by homogenization: within 5% of
// their targets after at most one L-BFGS step (Max iterations = 1 keeps the
// test short). p1, p2, p5 stay fixed, so the map is tileable (the joint
// radius p5 is the same everywhere): a query of the built map keeps them
// and gives the requested (E, nu). Bad Fixed parameters entries are clear
// errors.

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <cmath>

using namespace dealii;

namespace
{
  const std::string mesh = "subsection Mesh\n set Element size = 0.08\n"
                           " set Boundary element size = 0.04\nend\n";

  std::string
  build(const std::string &fixed)
  {
    return "set Dimension = 2\nset Mode = build map\nset Output directory = "
           "built\n" +
           mesh +
           "subsection Structure\n"
           " set Parameters = 0.25, 0.225, 0.5, 0.7, 0.23, 0.15, 0.1, 0.1\nend\n"
           "subsection Inverse\n set Proximity weight = 0.01\n"
           " set Max iterations = 1\n set Tolerance = 0.05\n"
           " set Free parameters = p3, p4, p6, p7, p8\nend\n"
           "subsection Map\n set Initial map = transversal\n"
           " set Fixed parameters = " +
           fixed +
           "\n set Sampling ranges = p3 = 0.3:0.6, p4 = 0.6:0.9, p6 = "
           "0.05:0.3, p7 = 0.05:0.15, p8 = 0.05:0.2\n"
           " set Subspace samples = 2\n set Transversal grid samples = 4\n"
           " set Young's moduli = 0.02:0.12:11\n"
           " set Poisson's ratios = -0.1:0.4:11\n set Angles = 90\n"
           " set Spline control points = 4, 4, 4\n set Accuracy checks = 0\n"
           "end\n";
  }
} // namespace

int
main()
{
  initlog();
  int code =
    run_app(FORMA_APP, "build", build("p1 = 0.25, p2 = 0.225, p5 = 0.23"));
  const auto  s = nlohmann::json::parse(read_file("built/summary.json"));
  const auto &t = s["transversal"];
  deallog << "build map: exit code " << code << ", normals "
          << t["normals"].size() << " x " << t["normals"][0].size() << ", free "
          << t["free"].dump() << ", targets inside H'(V) "
          << t["targets_covered"].get<unsigned int>() << " of 121 "
          << t["covered"].dump() << ", their starts within 5% "
          << t["targets_reached"].get<unsigned int>() << std::endl;

  code         = run_app(FORMA_APP,
                 "query",
                 "set Dimension = 2\nset Mode = query\nset Output directory "
                         "= query\n" +
                   mesh +
                   "subsection Map\n set Map file = built/map.json\nend\n"
                           "subsection Query\n set Young's modulus = 0.1\n"
                           " set Poisson's ratio = 0.4\n set Angle = 90\nend\n");
  const auto q = nlohmann::json::parse(read_file("query/summary.json"));
  const auto p = q["structure"]["p"];
  deallog << "query: exit code " << code << ", p1 " << p[0].get<double>()
          << ", p2 " << p[1].get<double>() << ", p5 "
          << std::round(1e6 * p[4].get<double>()) / 1e6 << ", |E/E* - 1| "
          << (std::abs(q["E_relative_error"].get<double>()) < 0.05 ? "< 0.05" :
                                                                     "LARGE")
          << ", |nu - nu*| "
          << (std::abs(q["nu_error"].get<double>()) < 0.03 ? "< 0.03" : "LARGE")
          << std::endl;

  for (const std::string bad : {"p9 = 0.5",
                                "p1 0.5",
                                "p5 = 0.9",
                                "p5 = 0.2, p5 = 0.3",
                                "p1 = 0.25, p2 = 0.225, p3 = 0.5, p5 = 0.23"})
    {
      code                = run_app(FORMA_APP, "bad", build(bad));
      std::string message = read_file("bad.stderr");
      const auto  at      = message.find("Fixed parameters");
      deallog << "'" << bad << "': exit code " << (code != 0 ? "non-zero" : "0")
              << ", "
              << (at != std::string::npos ?
                    message.substr(at, message.find('\n', at) - at) :
                    "no message")
              << std::endl;
    }
}
