// Bad input to forma-rhombic is rejected with a message that names the
// problem, a non-zero exit code, and the results of an earlier good run
// untouched.

#include "../tests.h"

const std::string base = "set Output directory = results\n"
                         "subsection Mesh\n set Element size = 0.1\n"
                         " set Boundary element size = 0.05\nend\n"
                         "subsection Output\n set Write vtu = false\nend\n";

int
main()
{
  initlog();
  const int         ok   = run_app(FORMA_APP, "good", base);
  const std::string good = read_file("results/summary.json");
  dealii::deallog << "good run: exit code " << ok << std::endl;

  const auto structure = [&](const std::string &entries) {
    return base + "subsection Structure\n" + entries + "end\n";
  };
  expect_failure("seven_parameters",
                 structure(" set Parameters = 0.3, 0.3, 0.5, 0.5, 0.2, "
                           "0.1, 0.1\n"),
                 good);
  expect_failure("radius_out_of_range",
                 structure(" set Parameters = 0.3, 0.3, 0.5, 0.5, 0.9, "
                           "0.1, 0.1, 0.1\n"),
                 good);
  expect_failure("node_2_outside",
                 structure(" set Parameters = 0.6, 0.6, 0.5, 0.5, 0.2, "
                           "0.1, 0.1, 0.1\n"),
                 good);
  expect_failure("not_a_number",
                 structure(" set Parameters = 0.3, 0.3, x, 0.5, 0.2, "
                           "0.1, 0.1, 0.1\n"),
                 good);
  expect_failure("angle_too_small", structure(" set Angle = 10\n"), good);
  expect_failure("boundary_size_above_size",
                 base + "subsection Mesh\n set Boundary element size = 0.2\n"
                        "end\n",
                 good);
  expect_failure("three_dimensions", base + "set Dimension = 3\n", good);
  expect_failure("empty_sweep",
                 base + "set Mode = sweep\nsubsection Sweep\n set p1 = 0.6\n"
                        " set p2 = 0.6\nend\n",
                 good);
  expect_failure("bad_sweep_range",
                 base + "set Mode = sweep\nsubsection Sweep\n"
                        " set p3 = 0.1:0.5\nend\n",
                 good);
  expect_failure("unknown_mode", base + "set Mode = optimize\n", good);
  expect_failure("inverse_start_joined_at_corner",
                 base +
                   "set Mode = inverse\nsubsection Inverse\n"
                   " set Free parameters = p1\nend\n" +
                   "subsection Structure\n set Angle = 46.875\n"
                   " set Parameters = 0.1, 0.05, 0.5, 0.91, 0.3, 0.1, 0.05, "
                   "0.05\nend\n",
                 good);

  // Quad meshes and the two-scale pipeline.
  std::ofstream("no_physicals.geo")
    << "Point(1) = {0, 0, 0};\nPoint(2) = {1, 0, 0};\nPoint(3) = {1, 1, 0};\n"
       "Point(4) = {0, 1, 0};\nLine(1) = {1, 2};\nLine(2) = {2, 3};\n"
       "Line(3) = {3, 4};\nLine(4) = {4, 1};\nCurve Loop(1) = {1, 2, 3, 4};\n"
       "Plane Surface(1) = {1};\n";
  expect_failure("quad_mesh_without_physicals",
                 base + "set Mode = rhombic mesh\nsubsection Quad mesh\n"
                        " set File = no_physicals.geo\nend\n",
                 good);
  expect_failure("quad_mesh_missing",
                 base + "set Mode = rhombic mesh\nsubsection Quad mesh\n"
                        " set File = missing.msh\nend\n",
                 good);
  const std::string two_scale =
    base + "set Mode = two-scale design\nsubsection Quad mesh\n set File = " +
    std::string(FORMA_SOURCE_DIR) +
    "/parameter_files/rhombic/meshes/bar.geo\n set Element size = 0.5\nend\n"
    "subsection Map\n set Map file = " +
    std::string(FORMA_SOURCE_DIR) + "/contrib/rhombic/map.json\nend\n";
  expect_failure("macro_problem_missing",
                 two_scale + "subsection Two-scale\n set Macro problem = "
                             "missing.prm\nend\n",
                 good);
  std::ofstream("macro_per_body.prm")
    << "set Mode = optimize\nsubsection Material\n set Plane = stress\nend\n"
       "subsection Design\n set Parameters = material\nend\n";
  expect_failure("macro_problem_not_per_cell",
                 two_scale + "subsection Two-scale\n set Macro problem = "
                             "macro_per_body.prm\nend\n",
                 good);
  expect_failure("macro_settings_unknown_entry",
                 two_scale + "subsection Two-scale\n set Macro problem = "
                             "macro_per_body.prm\n set Macro settings = "
                             "Optimization/Max iterations=8 | "
                             "Optimization/Max iteration=8\nend\n",
                 good);
  expect_failure("pointwise_table_not_given",
                 two_scale + "subsection Two-scale\n set Macro problem = "
                             "macro_per_body.prm\n set Baselines = pointwise "
                             "table\nend\n",
                 good);
  std::ofstream("broken_table.json")
    << "{\"format\": \"forma-rhombic material map 1\", \"entries\": []}";
  expect_failure("pointwise_table_broken",
                 two_scale + "subsection Two-scale\n set Macro problem = "
                             "macro_per_body.prm\n set Baselines = pointwise "
                             "table\n set Pointwise table = broken_table.json"
                             "\nend\n",
                 good);

  // Inverse bounds and map extensions.
  expect_failure("bounds_outside_geometry",
                 base + "set Mode = inverse\nsubsection Inverse\n"
                        " set Parameter bounds = p8 = 0.001:0.3\nend\n",
                 good);
  expect_failure("bounds_not_a_range",
                 base + "set Mode = inverse\nsubsection Inverse\n"
                        " set Parameter bounds = p8 = 0.03\nend\n",
                 good);
  const std::string extension =
    base +
    "set Mode = build map\nsubsection Map\n set Initial map = file\n"
    " set Young's moduli = 0.02:0.1:5\n set Poisson's ratios = "
    "0:0.4:5\n set Initial map file = " +
    std::string(FORMA_SOURCE_DIR) + "/contrib/rhombic/map.json\n";
  expect_failure("extension_above_the_map",
                 extension + " set Angles = 95\nend\n",
                 good);
  expect_failure("extension_other_grid",
                 extension + " set Angles = 55\n set Poisson's ratios = "
                             "0:0.4:4\nend\n",
                 good);
  expect_failure("extension_without_file",
                 base + "set Mode = build map\nsubsection Map\n"
                        " set Initial map = file\n set Angles = 55\nend\n",
                 good);
}
