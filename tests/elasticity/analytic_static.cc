// Static checks against closed forms:
//  - patch test: a homogeneous deformation prescribed on the boundary of a
//    non-affine mesh (hyper_ball) is reproduced to round-off, for linear and
//    Neo-Hookean materials in 2D and 3D;
//  - cantilever: Q2 tip deflection against Timoshenko beam theory, and the
//    support reaction against the applied load;
//  - Neo-Hookean uniaxial stretch with free lateral faces: lateral stretch and
//    nominal stress against the closed form.

#include <deal.II/base/function_parser.h>

#include <forma/elasticity/simulator.h>

#include "../tests.h"

using namespace dealii;

template <int dim>
forma::ElasticitySimulator<dim>
make(const std::string &prm)
{
  return forma::ElasticitySimulator<dim>(
    parameters_from_string<forma::ElasticityParameters>(
      "set Dimension = " + std::to_string(dim) + "\n" + prm),
    MPI_COMM_WORLD);
}

template <int dim>
void
patch_test(const std::string &model)
{
  const std::vector<std::string> u =
    dim == 2 ? std::vector<std::string>{"0.02*x - 0.03*y + 0.01",
                                        "0.01*x + 0.04*y - 0.02"} :
               std::vector<std::string>{"0.02*x - 0.03*y + 0.01*z",
                                        "0.01*x + 0.04*y",
                                        "-0.02*x + 0.01*y + 0.03*z + 0.01"};
  std::string expr;
  for (const auto &e : u)
    expr += (expr.empty() ? "" : ", ") + e;
  auto sim = make<dim>(
    "subsection Mesh\n set Generator = hyper_ball\n set Generator arguments = " +
    std::string(dim == 2 ? "0, 0" : "0, 0, 0") +
    " : 1 : false\n set Initial refinement = 1\nend\n"
    "subsection Material\n set Model = " +
    model +
    "\n set Bodies = * : E = 10, nu = 0.3\nend\n"
    "subsection Boundary conditions\n set Dirichlet = 0 : " +
    (dim == 2 ? "xy" : "xyz") + " : " + expr + "\nend\n" +
    "subsection Solver\n set Newton relative tolerance = 1e-14\nend\n");
  sim.run();
  FunctionParser<dim> exact(dim);
  exact.initialize(dim == 2 ? "x,y" : "x,y,z", u, {});
  // L2: FunctionParser gradients are finite differences (~1e-10).
  const double e = sim.error_norm(exact, false);
  deallog << dim << "D patch test (" << model
          << "): L2 error below 1e-12: " << (e < 1e-12 ? "yes" : "no")
          << std::endl;
}

void
cantilever()
{
  // L = 10, h = 1, plane stress, end shear load P = 0.1 (traction on x = L).
  const double E = 1000, nu = 0.3, L = 10, h = 1, P = 0.1;
  auto         sim = make<2>(
    "subsection Mesh\n set Generator = subdivided_hyper_rectangle\n"
            " set Generator arguments = 20, 2 : 0, 0 : 10, 1 : true\n"
            " set Initial refinement = 1\nend\n"
            "subsection Finite element\n set Degree = 2\nend\n"
            "subsection Material\n set Plane = stress\n set Bodies = * : E = 1000, nu = 0.3\nend\n"
            "subsection Boundary conditions\n set Dirichlet = 0 : xy : 0, 0\n"
            " set Traction = 1 : 0, -0.1\nend\n"
            "subsection Output\n set Points = 10, 0.5\nend\n");
  sim.run();
  const double I = h * h * h / 12, G = E / (2 * (1 + nu));
  const double timoshenko =
    P * L * L * L / (3 * E * I) + P * L / (5. / 6 * G * h);
  const double tip = -sim.steps().back().point_displacements[0][1];
  deallog << "cantilever tip deflection " << rounded(tip, 3) << ", Timoshenko "
          << rounded(timoshenko, 3) << ", within 1%: "
          << (std::abs(tip - timoshenko) < 0.01 * timoshenko ? "yes" : "no")
          << std::endl;
  const auto R = sim.reaction(0);
  deallog << "support reaction balances the load to 1e-9: "
          << (std::abs(R[1] - P) < 1e-9 && std::abs(R[0]) < 1e-9 ? "yes" : "no")
          << std::endl;
}

template <int dim>
void
uniaxial(const double stretch)
{
  // Unit cube, symmetry rollers on x=0, y=0 (z=0), stretch prescribed on x=1.
  const double E = 10, nu = 0.3;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)),
               mu     = E / (2 * (1 + nu));
  std::string bc =
    "0 : x : 0 ; 2 : y : 0 ; 1 : x : " + std::to_string(stretch - 1);
  if (dim == 3)
    bc += " ; 4 : z : 0";
  auto sim = make<dim>(
    "subsection Mesh\n set Generator = hyper_cube\n set Generator arguments = 0 : 1 : true\n"
    " set Initial refinement = 1\nend\n"
    "subsection Material\n set Model = neo-hookean\n set Bodies = * : E = 10, nu = 0.3\nend\n"
    "subsection Boundary conditions\n set Dirichlet = " +
    bc +
    "\nend\n"
    "subsection Time\n set Load steps = 4\nend\n"
    "subsection Output\n set Points = " +
    std::string(dim == 2 ? "1, 1" : "1, 1, 1") + "\nend\n");
  sim.run();
  // Closed form: lateral stress mu (l2 - 1/l2) + lambda log(J) / l2 = 0.
  double l2 = 1;
  for (int it = 0; it < 50; ++it)
    {
      const double J = stretch * std::pow(l2, dim - 1);
      const double g = mu * (l2 - 1 / l2) + lambda * std::log(J) / l2;
      const double dg =
        mu * (1 + 1 / (l2 * l2)) +
        lambda * ((dim - 1) / (l2 * l2) - std::log(J) / (l2 * l2));
      l2 -= g / dg;
    }
  const double J = stretch * std::pow(l2, dim - 1);
  const double P1 =
    mu * (stretch - 1 / stretch) + lambda * std::log(J) / stretch;
  const double lateral = 1 + sim.steps().back().point_displacements[0][1];
  const double force   = sim.reaction(1)[0]; // reference area 1
  deallog << dim << "D neo-hookean stretch " << stretch << ": lateral stretch "
          << rounded(lateral, 6) << " (closed form " << rounded(l2, 6)
          << "), nominal stress " << rounded(force, 6) << " (closed form "
          << rounded(P1, 6) << "), both to 1e-8: "
          << (std::abs(lateral - l2) < 1e-8 &&
                  std::abs(force - P1) < 1e-8 * std::abs(P1) ?
                "yes" :
                "no")
          << std::endl;
}

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  patch_test<2>("linear elastic");
  patch_test<2>("neo-hookean");
  patch_test<3>("linear elastic");
  patch_test<3>("neo-hookean");
  cantilever();
  uniaxial<2>(1.5);
  uniaxial<2>(0.7);
  uniaxial<3>(1.5);
}
