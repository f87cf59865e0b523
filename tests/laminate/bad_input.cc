// Bad input to forma-laminate is rejected with a message that names the
// problem, a non-zero exit code, and the results of an earlier good run
// untouched: parameters outside their ranges, malformed images, a
// structure without material, a 3D request, a malformed sweep range, a
// zero base modulus, a CLM ratio out of range, an
// unreachable inverse target, a table file that is not a sweep's.

#include "../tests.h"

#include <fstream>

const std::string base = "set Output directory = results\n"
                         "subsection Grid\n set Cells along height = 8\nend\n"
                         "subsection Output\n set Write vtu = false\nend\n";

int
main()
{
  initlog();
  std::ofstream("ring.csv") << "1,1,1,1\n1,0,0,1\n1,0,0,1\n1,1,1,1\n";
  std::ofstream("empty.csv") << "0,0,0\n0,0,0\n";
  std::ofstream("ragged.csv") << "0,1,0\n1,1\n";
  std::ofstream("range.csv") << "0,1.5\n1,1\n";
  std::ofstream("color.pgm") << "P3\n2 2\n255\n0 0 0 0 0 0 0 0 0 0 0 0\n";
  std::ofstream("short.pgm") << "P2\n3 3\n255\n0 255 0\n255\n";
  std::ofstream("huge.pgm") << "P5\n100000 100000\n255\n";

  const int ok =
    run_app(FORMA_APP,
            "good",
            base + "set Mode = homogenize\nsubsection Structure\n"
                   " set Type = image\n set Image file = ring.csv\nend\n");
  const std::string good = read_file("results/summary.json");
  dealii::deallog << "good image run: exit code " << ok << std::endl;

  auto image = [&](const std::string &file) {
    return base +
           "set Mode = homogenize\nsubsection Structure\n"
           " set Type = image\n set Image file = " +
           file + "\nend\n";
  };
  expect_failure("p1_out_of_range",
                 base + "set Mode = homogenize\nsubsection Structure\n"
                        " set p1 = 1.2\nend\n",
                 good);
  expect_failure("p3_zero",
                 base + "set Mode = homogenize\nsubsection Structure\n"
                        " set p3 = 0\nend\n",
                 good);
  expect_failure("adaptive_cycles_with_multigrid",
                 image("ring.csv") + "subsection Grid\n set Adaptive cycles = "
                                     "2\n set Solver = multigrid\nend\n",
                 good);
  expect_failure("empty_image", image("empty.csv"), good);
  expect_failure("ragged_csv", image("ragged.csv"), good);
  expect_failure("density_out_of_range", image("range.csv"), good);
  expect_failure("color_pgm", image("color.pgm"), good);
  expect_failure("truncated_pgm", image("short.pgm"), good);
  expect_failure("oversized_pgm", image("huge.pgm"), good);
  expect_failure("missing_image", image("nowhere.pgm"), good);
  expect_failure("three_dimensions",
                 base + "set Dimension = 3\nset Mode = homogenize\n",
                 good);
  expect_failure("bad_sweep_range",
                 base + "set Mode = sweep\nsubsection Sweep\n"
                        " set p1 = 0.5:0.9\nend\n",
                 good);
  expect_failure("zero_base_modulus",
                 base + "set Mode = homogenize\nsubsection Base material\n"
                        " set Young's modulus = 0\nend\n",
                 good);
  expect_failure("clm_ratio_out_of_range",
                 base + "set Mode = homogenize\nsubsection Base material\n"
                        " set CLM Poisson's ratios = 0.2, 0.7\nend\n",
                 good);
  expect_failure("sweep_beams_below_one",
                 base + "set Mode = sweep\nsubsection Sweep\n"
                        " set Beams per joint = 0.5\nend\n",
                 good);
  expect_failure("inverse_target_outside_hashin_shtrikman",
                 base + "set Mode = inverse\nsubsection Inverse\n"
                        " set Target Young's modulus = 0.9\n"
                        " set Target Poisson's ratio = 0.4\nend\n",
                 good);
  expect_failure("inverse_table_without_columns",
                 base + "set Mode = inverse\nsubsection Inverse\n"
                        " set Table file = ring.csv\nend\n",
                 good);
  expect_failure("inverse_shape_derivative_without_compliance",
                 base + "set Mode = inverse\nsubsection Inverse\n"
                        " set Report shape derivative = true\nend\n",
                 good);
}
