// Bad input is rejected with a message that names the problem, a non-zero
// exit code, and without touching the results of an earlier good run
// (summary.json stays byte-identical; the failed run's files go to
// failed-run/ with "status": "failed").

#include "../tests.h"

#include <fstream>

const std::string base =
  "set Output directory = results\n"
  "subsection Material\n set Bodies = * : E = 10, nu = 0.3\nend\n"
  "subsection Boundary conditions\n set Dirichlet = 0 : xy : 0, 0\n"
  " set Traction = 1 : 0, -0.1\nend\n";

int
main()
{
  initlog();
  // A mesh with a self-intersecting (bow-tie) quadrilateral.
  std::ofstream("bowtie.msh")
    << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n6\n"
       "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n5 2 1 0\n6 2 0 0\n"
       "$EndNodes\n$Elements\n2\n"
       "1 3 2 0 1 1 2 3 4\n2 3 2 0 1 2 6 3 5\n$EndElements\n";
  const int         code = run_app(FORMA_APP, "good", base);
  const std::string good = read_file("results/summary.json");
  dealii::deallog << "good run: exit code " << code << ", summary status ok: "
                  << (good.find("\"status\": \"ok\"") != std::string::npos ?
                        "yes" :
                        "no")
                  << std::endl;

  expect_failure("unknown_entry", base + "set Dimensoin = 3\n", good);
  expect_failure("wrong_value",
                 base + "subsection Time\n set BDF order = 7\nend\n",
                 good);
  expect_failure(
    "missing_mesh",
    base +
      "subsection Mesh\n set Source = file\n set File = missing.msh\nend\n",
    good);
  expect_failure(
    "inverted_element",
    base + "subsection Mesh\n set Source = file\n set File = bowtie.msh\nend\n",
    good);
  expect_failure(
    "incompressible",
    base + "subsection Material\n set Bodies = * : E = 10, nu = 0.5\nend\n",
    good);
  expect_failure(
    "unknown_boundary",
    base + "subsection Boundary conditions\n set Traction = 7 : 0, 1\nend\n",
    good);
  expect_failure(
    "bad_expression",
    base + "subsection Boundary conditions\n set Traction = 1 : 0, sin(\nend\n",
    good);
  expect_failure(
    "no_convergence",
    base + "subsection Material\n set Model = neo-hookean\nend\n"
           "subsection Boundary conditions\n set Traction = 1 : 0, -50\nend\n"
           "subsection Solver\n set Max Newton iterations = 3\nend\n",
    good);
  expect_failure("inverted_design",
                 base + "set Mode = verify gradient\n"
                        "subsection Design\n set Parameters = shape\n"
                        " set Shape perturbation = 0, -2*y\nend\n"
                        "subsection Objective\n set Terms = compliance\nend\n",
                 good);
  expect_failure("empty_design",
                 base + "set Mode = optimize\n"
                        "subsection Objective\n set Terms = compliance\nend\n",
                 good);
  expect_failure("unknown_objective",
                 base + "set Mode = optimize\n"
                        "subsection Design\n set Parameters = material\nend\n"
                        "subsection Objective\n set Terms = stres : p=2\nend\n",
                 good);
  expect_failure("resume_without_checkpoint",
                 base + "set Mode = optimize\n"
                        "subsection Design\n set Parameters = material\nend\n"
                        "subsection Objective\n set Terms = compliance\nend\n"
                        "subsection Optimization\n set Resume = true\nend\n",
                 good);
  expect_failure("remesh_cell_material",
                 base + "set Mode = optimize\n"
                        "subsection Design\n set Parameters = shape, cell "
                        "material\nend\n"
                        "subsection Objective\n set Terms = compliance\nend\n"
                        "subsection Optimization\n set Remesh quality = "
                        "0.5\nend\n",
                 good);
  // IPC contact: a geometry that already intersects, a body behind an
  // obstacle, a barrier distance above the mesh size, unknown obstacles,
  // gradients IPC does not cover (static friction over load steps), and
  // designs that do not fit the problem.
  std::ofstream("overlap.msh")
    << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n8\n"
       "1 0 0 0\n2 1 0 0\n3 1 1 0\n4 0 1 0\n"
       "5 0.8 0.5 0\n6 1.8 0.5 0\n7 1.8 1.5 0\n8 0.8 1.5 0\n"
       "$EndNodes\n$Elements\n2\n"
       "1 3 2 0 1 1 2 3 4\n2 3 2 1 2 5 6 7 8\n$EndElements\n";
  const std::string ipc =
    "subsection IPC\n set Enabled = true\n set Barrier distance = 0.01\nend\n";
  expect_failure("ipc_intersecting_input",
                 base + ipc +
                   "subsection Mesh\n set Source = file\n set File = "
                   "overlap.msh\nend\n"
                   "subsection Boundary conditions\n set Traction = \nend\n",
                 good);
  expect_failure("ipc_behind_plane",
                 base + ipc +
                   "subsection IPC\n set Obstacles = plane : 0, 0.5 : 0, "
                   "1\nend\n",
                 good);
  expect_failure("ipc_barrier_distance",
                 base + ipc +
                   "subsection IPC\n set Barrier distance = 2\nend\n",
                 good);
  expect_failure("ipc_unknown_obstacle",
                 base + ipc +
                   "subsection IPC\n set Obstacles = sphere : 0, 0 : "
                   "1\nend\n",
                 good);
  expect_failure("ipc_missing_obstacle_file",
                 base + ipc +
                   "subsection IPC\n set Obstacles = mesh : "
                   "no_such_ramp.msh\nend\n",
                 good);
  const std::string gradient = "set Mode = verify gradient\n"
                               "subsection Objective\n set Terms = "
                               "compliance\nend\n";
  expect_failure("ipc_static_friction_gradient",
                 base + ipc + gradient +
                   "subsection IPC\n set Friction coefficient = 0.3\nend\n"
                   "subsection Time\n set Load steps = 2\nend\n"
                   "subsection Design\n set Parameters = material\nend\n",
                 good);
  expect_failure("friction_design_without_ipc",
                 base + gradient +
                   "subsection Design\n set Parameters = friction\nend\n",
                 good);
  expect_failure("contact_force_without_ipc",
                 base + gradient +
                   "subsection Objective\n set Terms = contact force\nend\n"
                   "subsection Design\n set Parameters = material\nend\n",
                 good);
  expect_failure("contact_force_unknown_body",
                 base + ipc + gradient +
                   "subsection Objective\n set Terms = contact force : "
                   "material=7\nend\n"
                   "subsection Design\n set Parameters = material\nend\n",
                 good);
  expect_failure("design_start_count",
                 base + gradient +
                   "subsection Design\n set Parameters = material\n"
                   " set Start = material : 1e4\nend\n",
                 good);
  expect_failure("design_start_block",
                 base + gradient +
                   "subsection Design\n set Parameters = material\n"
                   " set Start = damping : 1, 2\nend\n",
                 good);
  expect_failure("missing_plugin",
                 "set Additional shared libraries = missing_plugin.so\n" + base,
                 good);
  expect_failure("unknown_form",
                 base + "subsection Loads\n set Additional forms = magnetic "
                        "field : B=1\nend\n",
                 good);
  // Adaptive time steps where they do not apply: static problems, BDF3.
  expect_failure("adaptive_static",
                 base + "subsection Time\n set Integrator = adaptive\nend\n",
                 good);
  expect_failure("adaptive_bdf6",
                 base + "subsection Time\n set Problem = transient\n"
                        " set Integrator = adaptive\n set BDF order = 6\nend\n",
                 good);
  expect_failure("variable_order_fixed_steps",
                 base + "subsection Time\n set Problem = transient\n"
                        " set Variable order = true\nend\n",
                 good);
  // The matrix-free solver where it does not apply: Q1, simplices, IPC.
  const std::string mg = "subsection Solver\n set Linear solver = cg-mg\nend\n";
  expect_failure("matrix_free_degree_1", base + mg, good);
  expect_failure("matrix_free_simplex",
                 base + mg +
                   "subsection Finite element\n set Degree = 2\nend\n"
                   "subsection Mesh\n set Generator = subdivided_hyper_"
                   "rectangle\n set Generator arguments = 2, 2 : 0, 0 : 1, 1 "
                   ": true\n set Convert to simplices = true\nend\n",
                 good);
  expect_failure("matrix_free_ipc",
                 base + mg + ipc +
                   "subsection Finite element\n set Degree = 2\nend\n",
                 good);
  // A mesh file of binary junk: the message quotes its bytes escaped and
  // cut, and failed-run/summary.json stays valid JSON (it once threw
  // nlohmann's invalid-UTF-8 error inside the error path and aborted).
  {
    std::string junk;
    for (unsigned int i = 0; i < 3000; ++i)
      junk += static_cast<char>((i * 37 + 131) % 256);
    std::ofstream("binary.msh", std::ios::binary) << junk;
  }
  expect_failure(
    "binary_mesh",
    base + "subsection Mesh\n set Source = file\n set File = binary.msh\nend\n",
    good);
  // The goal estimate needs an objective and adaptive cycles.
  expect_failure("goal_without_objective",
                 base + "subsection Finite element\n set Adaptivity = h\n"
                        " set Error indicator = goal\nend\n",
                 good);
  expect_failure("goal_without_adaptivity",
                 base + "subsection Finite element\n"
                        " set Error indicator = goal\nend\n"
                        "subsection Objective\n set Terms = stress : p=2\n"
                        "end\n",
                 good);
  // Transient adaptivity where it does not apply: hp, the goal estimate,
  // gradients (an adjoint over a sequence of meshes).
  const std::string moving =
    "subsection Time\n set Problem = transient\n set End time = 0.1\n"
    " set Time step = 0.05\nend\n";
  expect_failure("transient_hp",
                 base + moving +
                   "subsection Finite element\n set Adaptivity = hp\nend\n",
                 good);
  expect_failure("transient_goal",
                 base + moving +
                   "subsection Finite element\n set Adaptivity = h\n"
                   " set Error indicator = goal\nend\n"
                   "subsection Objective\n set Terms = stress : p=2\nend\n",
                 good);
  expect_failure("transient_adaptivity_gradient",
                 base + moving +
                   "set Mode = verify gradient\n"
                   "subsection Finite element\n set Adaptivity = h\nend\n"
                   "subsection Objective\n set Terms = stress : p=2\nend\n"
                   "subsection Design\n set Parameters = shape\nend\n",
                 good);
  // Refinement between outer iterations where it does not apply.
  const std::string optimize =
    "set Mode = optimize\n"
    "subsection Objective\n set Terms = stress : p=2\nend\n"
    "subsection Design\n set Parameters = shape\n"
    " set Fixed boundaries = 0\nend\n";
  expect_failure("outer_refinement_without_outer_iterations",
                 base + optimize +
                   "subsection Optimization\n set Outer step = refine\nend\n",
                 good);
  expect_failure("outer_refinement_without_adaptivity",
                 base + optimize +
                   "subsection Optimization\n set Outer step = refine\n"
                   " set Outer iterations = 2\nend\n",
                 good);
  // A parameter value that is not UTF-8 (a Latin-1 file name): quoted
  // escaped, and the echoed parameters still make valid JSON.
  expect_failure("latin1_file_name",
                 base + "subsection Mesh\n set Source = file\n"
                        " set File = caf\xe9.msh\nend\n",
                 good);
  dealii::deallog
    << "failed-run/summary.json is valid JSON: "
    << (nlohmann::json::parse(read_file("results/failed-run/summary.json"),
                              nullptr,
                              false)
            .is_discarded() ?
          "no" :
          "yes")
    << std::endl;
  dealii::deallog << "failed run recorded in failed-run/summary.json: "
                  << (read_file("results/failed-run/summary.json")
                            .find("\"status\": \"failed\"") !=
                          std::string::npos ?
                        "yes" :
                        "no")
                  << std::endl;
}
