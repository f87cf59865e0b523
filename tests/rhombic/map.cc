// The material-to-geometry map (thesis ch. 4.6): a small map built by
// continuation (2 x 2 isotropic targets on the square cell) reaches every
// node, writes a loadable map.json with coverage, and a query between its
// samples gives a structure whose homogenized (E, nu) are within a few
// percent of the request (and a structure.svg whose area is the volume
// fraction); extended to a smaller angle (Initial map = file)
// it keeps its samples and covers the new angle too; a build interrupted
// after its first angle and resumed (Map/Resume) gives the same samples, and
// refuses a progress file of other settings; a build that fails after its
// sampling keeps the progress file it wrote. The
// shipped map
// (contrib/rhombic/map.json) is queried off its samples at an angle between two
// of its angles, and for a base material with nu = 0.3 (the CLM transform,
// eq. 4.11), within its documented accuracy (doc/rhombic.md: E to 15% between
// its sparse samples, nu to 0.03). The tileable map (p5 = 0.3) is queried at
// the edge of its coverage between its two smallest angles (45 and 46.25
// degrees), where its splines change fastest, to within 3%. The wide map
// (E/E_b 0.01-0.3 on a log axis) gives an auxetic and a stiff material
// to within 2% in E and 0.01 in nu. A target
// outside the coverage is reported with the nearest covered point.

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace
{
  const std::string mesh = "subsection Mesh\n set Element size = 0.08\n"
                           " set Boundary element size = 0.04\nend\n";

  void
  query(const std::string &name,
        const std::string &map,
        const double       E,
        const double       nu,
        const double       angle,
        const double       base_nu,
        const double       tolerance_E,
        const double       tolerance_nu,
        const bool         coarse = true)
  {
    const int code = run_app(
      FORMA_APP,
      name,
      "set Dimension = 2\nset Mode = query\nset Output directory = " + name +
        "\n" + (coarse ? mesh : "") +
        "subsection Output\n set SVG cell side = 10\nend\n" +
        "subsection Base material\n set Poisson's ratio = " +
        std::to_string(base_nu) +
        "\nend\nsubsection Map\n set Map file = " + map +
        "\nend\nsubsection Query\n set Young's modulus = " + std::to_string(E) +
        "\n set Poisson's ratio = " + std::to_string(nu) +
        "\n set Angle = " + std::to_string(angle) + "\nend\n");
    const auto s = nlohmann::json::parse(read_file(name + "/summary.json"));
    // structure.svg: the cell's material, side 10 mm, outer loops and
    // holes oppositely oriented; its area over the cell's is the volume
    // fraction.
    double area = 0;
    {
      const std::string svg   = read_file(name + "/structure.svg");
      const auto        start = svg.find(" d=\"");
      AssertThrow(start != std::string::npos,
                  dealii::ExcMessage("structure.svg: no path"));
      std::istringstream                 path(svg.substr(start + 4));
      std::vector<std::array<double, 2>> loop;
      const auto                         close = [&]() {
        for (unsigned int k = 0; k < loop.size(); ++k)
          area += loop[k][0] * loop[(k + 1) % loop.size()][1] -
                  loop[(k + 1) % loop.size()][0] * loop[k][1];
        loop.clear();
      };
      char c;
      while (path >> c && c != '"')
        if (c == 'M' || c == 'L')
          {
            AssertThrow(c == 'L' || loop.empty(),
                        dealii::ExcMessage("structure.svg: an open loop"));
            std::array<double, 2> x;
            path >> x[0] >> x[1];
            AssertThrow(path, dealii::ExcMessage("structure.svg: bad path"));
            loop.push_back(x);
          }
        else if (c == 'Z')
          close();
      AssertThrow(loop.empty(),
                  dealii::ExcMessage("structure.svg: an open loop"));
      area = std::abs(area) / 2 / (100 * std::sin(angle * M_PI / 180));
    }
    dealii::deallog << name << ": exit code " << code << ", inside coverage "
                    << s["inside_coverage"].get<bool>() << ", |E/E* - 1| "
                    << (std::abs(s["E_relative_error"].get<double>()) <
                            tolerance_E ?
                          "< " + std::to_string(tolerance_E) :
                          "LARGE")
                    << ", |nu - nu*| "
                    << (std::abs(s["nu_error"].get<double>()) < tolerance_nu ?
                          "< " + std::to_string(tolerance_nu) :
                          "LARGE")
                    << ", structure.svg's area is the volume fraction: "
                    << (std::abs(area - s["result"]["phi"].get<double>()) <
                        1e-6)
                    << std::endl;
  }



  /// Mode = build map on the 2 x 2 grid into `directory`.
  int
  build_map(const std::string &directory,
            const std::string &inverse,
            const std::string &map)
  {
    return run_app(
      FORMA_APP,
      directory,
      "set Dimension = 2\nset Mode = build map\nset Output directory = " +
        directory + "\n" + mesh +
        "subsection Structure\n"
        " set Parameters = 0.3, 0.15, 0.5, 0.7, 0.17, 0.15, 0.1, 0.05\nend\n"
        "subsection Inverse\n set Proximity weight = 0.01\n" +
        inverse +
        "end\nsubsection Map\n set Young's moduli = 0.04, 0.06\n"
        " set Poisson's ratios = 0.2, 0.3\n"
        " set Spline control points = 4, 4, 4\n set Accuracy checks = 0\n" +
        map + "end\n");
  }
} // namespace

int
main()
{
  initlog();
  const int  code = build_map("built", "", " set Angles = 90\n");
  const auto s    = nlohmann::json::parse(read_file("built/summary.json"));
  dealii::deallog << "build map: exit code " << code << ", samples "
                  << s["samples"].get<unsigned int>() << " of 4, coefficients "
                  << s["coefficients"].get<unsigned int>()
                  << ", fit residual < 0.02: "
                  << (s["fit_residual"].get<double>() < 0.02) << std::endl;
  query("query_built", "built/map.json", 0.05, 0.25, 90, 0, 0.05, 0.03);

  // Initial map = file: the built map extended to 85 degrees keeps its 4
  // samples and continues every node from its 90 degree structure.
  const int extended =
    build_map("extended",
              " set Parameter bounds = p8 = 0.03:0.3\n",
              " set Initial map = file\n set Initial map file = "
              "built/map.json\n set Angles = 85\n");
  const auto e = nlohmann::json::parse(read_file("extended/summary.json"));
  dealii::deallog << "extend map: exit code " << extended << ", samples "
                  << e["samples"].get<unsigned int>() << ", inverse solves "
                  << e["inverse_solves"].get<unsigned int>() << ", angles "
                  << e["covered"].size() << ", covered at 85 degrees "
                  << e["covered"][1]["nodes"].get<unsigned int>() << " of 4"
                  << std::endl;
  query("query_extended", "extended/map.json", 0.05, 0.25, 87.5, 0, 0.05, 0.03);

  // Resume: a build killed after its 90 degree angle leaves
  // map_progress.json (the map without splines); run again with Resume it
  // solves only the 85 degree nodes and gives the extension's samples. A
  // complete build leaves no progress file. The progress file here is the
  // built map's; it records the built map's settings, which the resumed
  // run (with the extension's p8 bounds) refuses: its samples would not be
  // this build's. As if the build had had those bounds (its 90 degree
  // samples have p8 > 0.05, the bound is inactive there), it is resumed.
  auto progress = nlohmann::json::parse(read_file("built/map.json"));
  progress.erase("parameters");
  progress.erase("coverage_polygons");
  std::filesystem::create_directories("resumed/.forma-staging");
  std::ofstream("resumed/map_progress.json") << progress.dump();
  // What the kill left in the staging directory: the next run keeps it in
  // interrupted-run/ until one commits.
  std::ofstream("resumed/.forma-staging/log.txt") << "the killed run's log\n";
  const std::string resume_bounds = " set Parameter bounds = p8 = 0.03:0.3\n";
  const std::string resume_map = " set Resume = true\n set Angles = 90, 85\n";
  const int stale_code = build_map("resumed", resume_bounds, resume_map);
  dealii::deallog
    << "resume from other settings: exit code "
    << (stale_code != 0 ? "non-zero" : "0") << ", says which: "
    << (read_file("resumed.stderr")
          .find("Inverse/Parameter bounds = \"\" (now \"p8 = 0.03:0.3\")") !=
        std::string::npos)
    << ", progress file kept: "
    << std::filesystem::exists("resumed/map_progress.json")
    << ", the killed run's log kept: "
    << (read_file("resumed/interrupted-run/log.txt") ==
        "the killed run's log\n")
    << std::endl;
  progress["build_settings"]["Inverse/Parameter bounds"] = "p8 = 0.03:0.3";
  std::ofstream("resumed/map_progress.json") << progress.dump();
  const int  resumed = build_map("resumed", resume_bounds, resume_map);
  const auto rs      = nlohmann::json::parse(read_file("resumed/summary.json"));
  // The samples of two map files (the same to round-off).
  const auto same = [](const std::string &a, const std::string &b) {
    const auto x     = nlohmann::json::parse(read_file(a))["samples"];
    const auto y     = nlohmann::json::parse(read_file(b))["samples"];
    bool       equal = x.size() == y.size();
    for (unsigned int k = 0; equal && k < x.size(); ++k)
      for (unsigned int i = 0; i < x[k].size(); ++i)
        equal = equal &&
                std::abs(x[k][i].get<double>() - y[k][i].get<double>()) < 1e-10;
    return equal;
  };
  dealii::deallog << "resumed map: exit code " << resumed << ", inverse solves "
                  << rs["inverse_solves"].get<unsigned int>() << ", samples "
                  << rs["samples"].get<unsigned int>()
                  << ", the extension's samples: "
                  << same("resumed/map.json", "extended/map.json")
                  << ", progress file removed: "
                  << !std::filesystem::exists("resumed/map_progress.json")
                  << " (after the complete build: "
                  << !std::filesystem::exists("built/map_progress.json") << ")"
                  << ", interrupted-run removed: "
                  << !std::filesystem::exists("resumed/interrupted-run")
                  << std::endl;
  // The progress file as a build writes it: this one fails after its
  // sampling (its map file cannot be written), says so and points at the
  // resume, and keeps the file; the file holds the built map's samples
  // (none is dropped as a branch jump on this grid) and settings.
  const int  written   = build_map("written",
                                "",
                                " set Angles = 90\n"
                                   " set Map file = missing/map.json\n");
  const auto built_map = nlohmann::json::parse(read_file("built/map.json"));
  const auto written_progress =
    nlohmann::json::parse(read_file("written/map_progress.json"));
  const std::string written_error = read_file("written.stderr");
  dealii::deallog
    << "failed after the sampling: exit code "
    << (written != 0 ? "non-zero" : "0") << ", says why: "
    << (written_error.find("Map/Map file = missing/map.json") !=
          std::string::npos &&
        written_error.find("Map/Resume = true") != std::string::npos)
    << ", progress file with the built map's samples: "
    << same("written/map_progress.json", "built/map.json") << ", settings: "
    << (written_progress.at("build_settings") ==
          built_map.at("build_settings") &&
        built_map.at("build_settings").at("Inverse/Proximity weight") == "0.01")
    << ", splines: " << written_progress.contains("parameters") << std::endl;

  // With no new angle the extension only refits the splines.
  build_map("refit",
            "",
            " set Initial map = file\n set Initial map file = "
            "extended/map.json\n set Angles =\n"
            " set Spline control points = 5, 5, 4\n");
  const auto r = nlohmann::json::parse(read_file("refit/summary.json"));
  dealii::deallog << "refit map: samples " << r["samples"].get<unsigned int>()
                  << ", inverse solves "
                  << r["inverse_solves"].get<unsigned int>()
                  << ", coefficients " << r["coefficients"].get<unsigned int>()
                  << std::endl;
  query("query_shipped",
        std::string(FORMA_SOURCE_DIR) + "/contrib/rhombic/map.json",
        0.05,
        0.25,
        67.5,
        0,
        0.15,
        0.03,
        false);
  query("query_shipped_clm",
        std::string(FORMA_SOURCE_DIR) + "/contrib/rhombic/map.json",
        0.05,
        0.25 + 0.3 * 0.05,
        80,
        0.3,
        0.15,
        0.03,
        false);
  query("query_tileable_edge",
        std::string(FORMA_SOURCE_DIR) + "/contrib/rhombic/map_tileable.json",
        0.085,
        0.125,
        45.625,
        0,
        0.03,
        0.03,
        false);
  // The wide map (splines uniform in log E): an auxetic material at 80
  // degrees and a stiff one on the square cell, between its samples.
  const std::string wide =
    std::string(FORMA_SOURCE_DIR) + "/contrib/rhombic/map_wide.json";
  query("query_wide_auxetic", wide, 0.02, -0.2, 80, 0, 0.02, 0.01, false);
  query("query_wide_stiff", wide, 0.2, 0.28, 90, 0, 0.02, 0.01, false);

  // A target outside the coverage: the query says so and names the
  // nearest covered point, which lies on the coverage's boundary: a query
  // there is inside, one a little beyond it (towards the target) outside.
  // On the 5 x 5 map (one polygon in E, nu) and on the wide one (two
  // polygons in log E, nu; "beyond" is a step along E, nu, which moves
  // away from the region in log E too).
  const auto check_nearest = [&](const std::string &name,
                                 const std::string &map,
                                 const double       E,
                                 const double       nu,
                                 const double       angle) {
    const auto ask =
      [&](const std::string &run, const double E, const double nu) {
        std::ostringstream target;
        target << std::setprecision(17) << " set Young's modulus = " << E
               << "\n set Poisson's ratio = " << nu
               << "\n set Angle = " << angle << "\n";
        run_app(FORMA_APP,
                run,
                "set Dimension = 2\nset Mode = query\nset Output directory = " +
                  run + "\n" + mesh +
                  "subsection Output\n set Write vtu = false\nend\n"
                  "subsection Map\n set Map file = " +
                  map + "\nend\nsubsection Query\n" + target.str() + "end\n");
        return nlohmann::json::parse(read_file(run + "/summary.json"));
      };
    const double x[2]    = {E, nu};
    const auto   outside = ask(name + "_outside", x[0], x[1]);
    const auto p = outside["nearest_covered_point"].get<std::vector<double>>();
    const double d      = std::hypot(x[0] - p[0], x[1] - p[1]);
    const auto   near   = ask(name + "_nearest", p[0], p[1]);
    const auto   beyond = ask(name + "_beyond",
                            p[0] + 1e-3 * (x[0] - p[0]) / d,
                            p[1] + 1e-3 * (x[1] - p[1]) / d);
    dealii::deallog << name << ": query outside the coverage: inside "
                    << outside["inside_coverage"].get<bool>()
                    << "; at the nearest covered point: inside "
                    << near["inside_coverage"].get<bool>()
                    << "; 0.001 beyond it: inside "
                    << beyond["inside_coverage"].get<bool>() << std::endl;
  };
  check_nearest("5x5",
                std::string(FORMA_SOURCE_DIR) + "/contrib/rhombic/map.json",
                0.5,
                0.2,
                75);
  check_nearest("wide", wide, 0.3, -0.2, 75);
}
