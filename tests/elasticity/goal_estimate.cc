// The goal-oriented (dual-weighted residual) estimate against an exact
// solution: u_x = atan(50 (x + y - 1)) on the unit square (a steep internal
// layer, body force and Dirichlet data from the manufactured solution), the
// goal J = ||sigma||_L2, known in closed form. On uniform, Kelly- and
// goal-refined meshes the estimate eta of J - J_h has effectivity
// eta / (J - J_h) in [0.5, 2] once the layer is resolved (below it, the adjoint
// one degree higher on the same mesh cannot see it either: the estimate is
// low), and goal refinement reaches uniform refinement's finest error with
// fewer DoFs than uniform and Kelly refinement.

#include <forma/elasticity/simulator.h>

#include "../tests.h"
#include "layer_problem.h"

#include <cmath>

using namespace dealii;

const double lambda = 1.5, mu = 1, a = 50;
// ||sigma||_L2: with g = a / (1 + a^2 s^2), s = x + y - 1, grad u_x =
// (g, g) and |sigma|^2 = g^2 ((lambda + 2 mu)^2 + 2 mu^2 + lambda^2); the
// integral of g(s)^2 over the square is int_-1^1 g^2 (1 - |s|) ds.
double
exact_goal()
{
  const double a2 = a * a;
  const double G  = 2. * (a * (a / (2. * (1. + a2)) + std::atan(a) / 2.) -
                         0.5 * (1. - 1. / (1. + a2)));
  const double c = std::pow(lambda + 2 * mu, 2) + 2 * mu * mu + lambda * lambda;
  return std::sqrt(c * G);
}

std::vector<forma::ElasticitySimulator<2>::CycleRecord>
study(const std::string &indicator,
      const double       fraction,
      const unsigned     cycles)
{
  const auto p = parameters_from_string<forma::ElasticityParameters>(
    layer_problem(2,
                  " set Degree = 2\n set Adaptivity = h\n"
                  " set Error indicator = " +
                    indicator +
                    "\n set Goal estimate = true\n"
                    " set Refine fraction = " +
                    std::to_string(fraction) +
                    "\n set Adaptive cycles = " + std::to_string(cycles) + "\n",
                  "subsection Objective\n set Terms = stress : p=2\nend\n"));
  forma::ElasticitySimulator<2> sim(p, MPI_COMM_WORLD);
  sim.run();
  return sim.cycles();
}

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const double J = exact_goal();
  deallog << "exact J = " << rounded(J, 8) << std::endl;
  std::map<std::string, std::vector<std::pair<double, double>>> errors;
  for (const auto &[name, indicator, fraction, cycles] :
       std::vector<std::tuple<std::string, std::string, double, unsigned>>{
         {"uniform", "kelly", 1., 4},
         {"kelly", "kelly", 0.3, 7},
         {"goal", "goal", 0.3, 7}})
    {
      bool effective = true;
      deallog << name << ": (DoFs, error, effectivity)";
      for (const auto &c : study(indicator, fraction, cycles))
        {
          const double e   = J - c.objective;
          const double eff = c.estimate / e;
          if (std::abs(e) < 1e-3 * J)
            effective &= eff > 0.5 && eff < 2.;
          errors[name].emplace_back(c.n_dofs, std::abs(e));
          deallog << " (" << c.n_dofs << ", " << rounded(e, 2) << ", "
                  << rounded(eff, 2) << ")";
        }
      deallog << std::endl
              << name
              << ": effectivity in [0.5, 2] where |J - J_h| < 0.1% of J: "
              << (effective ? "yes" : "no") << std::endl;
    }
  // The DoFs each adaptive run needs for uniform refinement's finest error.
  const auto [n_uniform, e_uniform] = errors["uniform"].back();
  const auto reach = [&, e = e_uniform](const std::string &name) {
    for (const auto &[n, error] : errors[name])
      if (error <= e)
        return n;
    return 1e300;
  };
  deallog << "uniform's finest error: goal refinement needs under half its "
             "DoFs: "
          << (2 * reach("goal") < n_uniform ? "yes" : "no")
          << ", fewer than Kelly: "
          << (reach("goal") < reach("kelly") ? "yes" : "no") << std::endl;
}
