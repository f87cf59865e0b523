// Bad contact input to forma-contact-assembly is rejected with a message
// that names the problem, a non-zero exit code, and the results of an
// earlier good run untouched.

#include "../tests.h"

#include <filesystem>

const std::string base = "set Dimension = 2\n"
                         "set Output directory = results\n"
                         "subsection Mesh\n set Source = file\n"
                         " set File = stack_2d.msh\nend\n"
                         "subsection Material\n"
                         " set Bodies = * : E = 1, nu = 0.3\nend\n"
                         "subsection Boundary conditions\n"
                         " set Dirichlet = 4 : x : 0\n"
                         " set Traction = 3 : 0, -0.01\nend\n"
                         "subsection Output\n set Write vtu = false\nend\n";

std::string
contact(const std::string &entries)
{
  return base + "subsection Contact\n" + entries + "end\n";
}

std::string
separated(const std::string &cut, const std::string &entries)
{
  return contact(entries) +
         "subsection Mesh\n set Separate interfaces = " + cut + "\nend\n";
}

int
main()
{
  initlog();
  // A local copy: messages name the file as given, without machine paths.
  std::filesystem::copy_file(
    std::string(FORMA_SOURCE_DIR) +
      "/parameter_files/contact_assembly/meshes/stack_2d.msh",
    "stack_2d.msh",
    std::filesystem::copy_options::overwrite_existing);
  const int         ok   = run_app(FORMA_APP,
                         "good",
                         separated("1-2 : 10",
                                   " set Rigid-deformable = 2 : alpha=1e-3\n"
                                             " set Deformable-deformable = 10 : "
                                             "alpha=1e-3\n"));
  const std::string good = read_file("results/summary.json");
  dealii::deallog << "good run: exit code " << ok << std::endl;

  expect_failure("unknown_key",
                 contact(" set Rigid-deformable = 2 : alpha=1e-3, beta=2\n"),
                 good);
  expect_failure("negative_alpha",
                 contact(" set Rigid-deformable = 2 : alpha=-1\n"),
                 good);
  expect_failure("missing_boundary",
                 contact(" set Rigid-deformable = 7 : alpha=1e-3\n"),
                 good);
  expect_failure("both_kinds",
                 separated("1-2 : 10",
                           " set Rigid-deformable = 10 : alpha=1e-3\n"
                           " set Deformable-deformable = 10 : alpha=1e-3\n"),
                 good);
  expect_failure("no_partner",
                 separated("1-2 : 10",
                           " set Deformable-deformable = 5 : alpha=1e-3\n"),
                 good);
  expect_failure("interface_not_cut",
                 contact(" set Deformable-deformable = 10 : alpha=1e-3\n"),
                 good);
  expect_failure("neo_hookean",
                 contact(" set Rigid-deformable = 2 : alpha=1e-3\n") +
                   "subsection Material\n set Model = neo-hookean\nend\n",
                 good);
  expect_failure("friction_with_cg",
                 contact(" set Rigid-deformable = 2 : alpha=1e-3, mu=0.3\n") +
                   "subsection Solver\n set Linear solver = cg-amg\nend\n",
                 good);
  expect_failure("objective_id",
                 contact(" set Rigid-deformable = 2 : alpha=1e-3\n") +
                   "set Mode = verify gradient\n"
                   "subsection Design\n set Parameters = shape\nend\n"
                   "subsection Objective\n set Terms = assembly : "
                   "boundary=2.5, material=0, y=1\nend\n",
                 good);
  expect_failure("gap_not_rigid_deformable",
                 contact(" set Rigid-deformable = 2 : alpha=1e-3\n"
                         " set Rigid gaps = 5 : 1\n"),
                 good);
  expect_failure("gap_bad_expression",
                 contact(" set Rigid-deformable = 2 : alpha=1e-3\n"
                         " set Rigid gaps = 2 : 1 +* x\n"),
                 good);
  expect_failure("gap_with_shape_design",
                 contact(" set Rigid-deformable = 2 : alpha=1e-3\n"
                         " set Rigid gaps = 2 : 0.01\n") +
                   "set Mode = verify gradient\n"
                   "subsection Design\n set Parameters = shape\nend\n",
                 good);
  expect_failure("goal_estimate_with_contact",
                 contact(" set Rigid-deformable = 2 : alpha=1e-3\n") +
                   "subsection Finite element\n set Adaptivity = h\n"
                   " set Error indicator = goal\nend\n"
                   "subsection Objective\n set Terms = compliance\nend\n",
                 good);
  expect_failure("materials_not_adjacent", separated("1-3 : 10", ""), good);
  expect_failure("bad_cut_syntax", separated("1 : 10", ""), good);
  expect_failure("element_removal_without_boundary",
                 contact(" set Rigid-deformable = 2 : alpha=1e-3\n") +
                   "set Mode = optimize\n"
                   "subsection Design\n set Parameters = shape\nend\n"
                   "subsection Objective\n set Terms = stress : p=4\nend\n"
                   "subsection Optimization\n set Element removal = 0.1\n"
                   "end\n",
                 good);
  expect_failure("element_removal_on_support",
                 contact(" set Rigid-deformable = 2 : alpha=1e-3\n") +
                   "set Mode = optimize\n"
                   "subsection Design\n set Parameters = shape\nend\n"
                   "subsection Objective\n set Terms = stress : p=4\nend\n"
                   "subsection Optimization\n set Element removal = 0.1\n"
                   " set Element removal boundary = 2\nend\n",
                 good);
  expect_failure("transient",
                 contact(" set Rigid-deformable = 2 : alpha=1e-3\n") +
                   "subsection Time\n set Problem = transient\nend\n",
                 good);
  const std::string optimize = contact(" set Rigid-deformable = 2 : "
                                       "alpha=1e-3\n") +
                               "set Mode = optimize\n"
                               "subsection Design\n set Parameters = shape\n"
                               "end\n";
  expect_failure("objective_unknown_key",
                 optimize + "subsection Objective\n set Terms = stress : "
                            "p=4, wieght=2\nend\n",
                 good);
  expect_failure("final_weight_without_outer_iterations",
                 optimize + "subsection Objective\n set Terms = stress : "
                            "p=4, final weight=10\nend\n",
                 good);
  expect_failure("inner_iterations_without_outer_iterations",
                 optimize +
                   "subsection Objective\n set Terms = stress : p=4\nend\n"
                   "subsection Optimization\n set Inner iterations = 5\nend\n",
                 good);
  expect_failure("element_removal_with_outer_iterations",
                 optimize +
                   "subsection Objective\n set Terms = stress : p=4\nend\n"
                   "subsection Optimization\n set Element removal = 0.1\n"
                   " set Element removal boundary = 3\n"
                   " set Outer iterations = 3\nend\n",
                 good);
  expect_failure("volume_minimization_without_stress_term",
                 optimize +
                   "subsection Objective\n set Terms = compliance\nend\n"
                   "subsection Optimization\n set Volume minimization "
                   "iterations = 5\nend\n",
                 good);
  expect_failure("volume_minimization_with_two_stress_terms",
                 optimize +
                   "subsection Objective\n set Terms = stress : p=4 ; von "
                   "mises : p=8\nend\n"
                   "subsection Optimization\n set Volume minimization "
                   "iterations = 5\nend\n",
                 good);
  // Singular problems: the top part cut off, held in x only,
  // one part held in x only, two parts in contact held by nothing else,
  // a Newton iteration limit and the top part pulled off its contact.
  expect_failure("cut_part_held_in_x_only",
                 separated("1-2 : 10",
                           " set Rigid-deformable = 2 : alpha=1e-3\n"),
                 good);
  expect_failure("part_held_in_x_only", contact(""), good);
  expect_failure("parts_holding_only_each_other",
                 separated("1-2 : 10",
                           " set Deformable-deformable = 10 : alpha=1e-3\n") +
                   "subsection Boundary conditions\n set Dirichlet =\nend\n",
                 good);
  expect_failure("newton_iteration_limit",
                 separated("1-2 : 10",
                           " set Rigid-deformable = 2 : alpha=1e-3\n"
                           " set Deformable-deformable = 10 : alpha=1e-3\n") +
                   "subsection Solver\n set Max Newton iterations = 1\nend\n",
                 good);
  expect_failure("part_pulled_off_its_contact",
                 separated("1-2 : 10",
                           " set Rigid-deformable = 2 : alpha=1e-3\n"
                           " set Deformable-deformable = 10 : alpha=1e-3\n") +
                   "subsection Boundary conditions\n"
                   " set Traction = 3 : 0, 0.01\nend\n",
                 good);
}
