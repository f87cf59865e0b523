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
}
