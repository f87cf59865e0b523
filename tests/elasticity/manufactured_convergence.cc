// Convergence against a manufactured solution (linear elasticity, body force
// f = -div sigma(u_exact), Dirichlet data u_exact on the whole boundary):
// L2 errors must fall at rate p+1 and H1 errors at rate p, for Q1/Q2 and
// P1/P2 in 2D and 3D.

#include <deal.II/base/function_parser.h>

#include <forma/elasticity/simulator.h>

#include "../tests.h"

using namespace dealii;

const std::string constants = "lambda = 1.5, mu = 1";
const std::string u2[] = {"sin(pi*x)*sin(pi*y)", "x*y*(1 - x)*cos(pi*y/2)"};
const std::string f2 =
  "-pi*lambda*x*y*sin(pi*y/2) + 2*lambda*x*cos(pi*y/2) + "
  "pi*lambda*y*sin(pi*y/2)/2 + pi^2*lambda*sin(pi*x)*sin(pi*y) - "
  "lambda*cos(pi*y/2) - pi*mu*x*y*sin(pi*y/2) + 2*mu*x*cos(pi*y/2) + "
  "pi*mu*y*sin(pi*y/2)/2 + 3*pi^2*mu*sin(pi*x)*sin(pi*y) - mu*cos(pi*y/2), "
  "-pi*lambda*(pi*x*y*(x - 1)*cos(pi*y/2) + 4*x*(x - 1)*sin(pi*y/2) + "
  "4*pi*cos(pi*x)*cos(pi*y))/4 - pi*mu*x*(x - 1)*(pi*y*cos(pi*y/2) + "
  "4*sin(pi*y/2))/2 + mu*(2*y*cos(pi*y/2) - pi^2*cos(pi*x)*cos(pi*y))";
const std::string u3[] = {"sin(pi*x)*sin(pi*y)*sin(pi*z)",
                          "x*y*z*(1 - x)",
                          "y*sin(pi*z)"};
const std::string f3 =
  "2*lambda*x*z - lambda*z + pi^2*lambda*sin(pi*x)*sin(pi*y)*sin(pi*z) + "
  "2*mu*x*z - mu*z + 4*pi^2*mu*sin(pi*x)*sin(pi*y)*sin(pi*z), "
  "-pi*lambda*(pi*sin(pi*z)*cos(pi*x)*cos(pi*y) + cos(pi*z)) + mu*(2*y*z - "
  "pi^2*sin(pi*z)*cos(pi*x)*cos(pi*y)) - pi*mu*cos(pi*z), "
  "lambda*(x*(x - 1) + pi^2*y*sin(pi*z) - pi^2*sin(pi*y)*cos(pi*x)*cos(pi*z)) "
  "+ mu*x*(x - 1) + 2*pi^2*mu*y*sin(pi*z) - pi^2*mu*sin(pi*y)*cos(pi*x)*cos(pi*z)";

template <int dim>
void
study(const unsigned int degree,
      const bool         simplex,
      const unsigned int r0,
      const unsigned int r1)
{
  const std::string *u = dim == 2 ? u2 : u3;
  std::string        exact, dirichlet;
  for (unsigned int d = 0; d < dim; ++d)
    exact += (d ? ", " : "") + u[d];
  for (unsigned int b = 0; b < 2 * dim; ++b)
    dirichlet += std::to_string(b) + " : " + (dim == 2 ? "xy" : "xyz") + " : " +
                 exact + (b + 1 < 2 * dim ? " ; " : "");

  std::vector<double> h, e0, e1;
  for (unsigned int r = r0; r <= r1; ++r)
    {
      const std::string prm =
        "set Dimension = " + std::to_string(dim) + "\n" +
        "subsection Mesh\n set Generator = hyper_cube\n"
        " set Generator arguments = 0 : 1 : true\n"
        " set Convert to simplices = " +
        (simplex ? "true" : "false") + "\n" +
        " set Initial refinement = " + std::to_string(r) + "\nend\n" +
        "subsection Finite element\n set Degree = " + std::to_string(degree) +
        "\nend\n" +
        "subsection Material\n set Bodies = * : lambda = 1.5, mu = 1\nend\n" +
        "subsection Boundary conditions\n set Dirichlet = " + dirichlet +
        "\n set Constants = " + constants + "\nend\n" +
        "subsection Loads\n set Body force = " + (dim == 2 ? f2 : f3) +
        "\nend\n";
      const auto parameters =
        parameters_from_string<forma::ElasticityParameters>(prm);
      forma::ElasticitySimulator<dim> sim(parameters, MPI_COMM_WORLD);
      sim.run();
      FunctionParser<dim> solution(dim);
      solution.initialize(dim == 2 ? "x,y" : "x,y,z",
                          std::vector<std::string>(u, u + dim),
                          {{"pi", numbers::PI}});
      h.push_back(std::pow(0.5, r));
      e0.push_back(sim.error_norm(solution, false));
      e1.push_back(sim.error_norm(solution, true));
    }
  for (unsigned int i = 0; i < h.size(); ++i)
    deallog << "  h = " << h[i] << ": L2 error " << rounded(e0[i])
            << ", H1 error " << rounded(e1[i]) << std::endl;
  const auto r_l2 = observed_rates(h, e0);
  const auto r_h1 = observed_rates(h, e1);
  deallog << dim << "D " << (simplex ? "P" : "Q") << degree << ": L2 rate "
          << rounded(r_l2.back(), 2) << " (expect " << degree + 1
          << "), H1 rate " << rounded(r_h1.back(), 2) << " (expect " << degree
          << ")" << std::endl;
  deallog << "  rates within 0.15 of the theory: "
          << ((std::abs(r_l2.back() - (degree + 1)) < 0.15 &&
               std::abs(r_h1.back() - degree) < 0.15) ?
                "yes" :
                "no")
          << std::endl;
}

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  study<2>(1, false, 3, 5);
  study<2>(2, false, 2, 4);
  study<2>(1, true, 2, 4);
  study<2>(2, true, 2, 4);
  study<3>(1, false, 1, 3);
  study<3>(2, false, 1, 2);
  study<3>(1, true, 1, 3);
  study<3>(2, true, 1, 2);
}
