// Adaptivity pays off: for a solution with a steep internal layer
// (u_x = atan(50 (x + y - 1)), body force from the manufactured solution)
// Kelly-driven h refinement and hp refinement reach a smaller error per DoF
// than uniform refinement.

#include <deal.II/base/function_parser.h>

#include <forma/elasticity/simulator.h>

#include "../tests.h"
#include "layer_problem.h"

using namespace dealii;

// Error (H1 seminorm) and DoFs per cycle.
std::vector<std::pair<double, double>>
study(const std::string &adaptivity,
      const unsigned int degree,
      const unsigned int cycles)
{
  const auto p = parameters_from_string<forma::ElasticityParameters>(
    layer_problem(2,
                  " set Degree = " + std::to_string(degree) +
                    "\n set Adaptivity = " + adaptivity +
                    "\n set Adaptive cycles = " + std::to_string(cycles) +
                    "\n"));
  forma::ElasticitySimulator<2>          sim(p, MPI_COMM_WORLD);
  std::vector<std::pair<double, double>> history;
  FunctionParser<2>                      u(2);
  u.initialize("x,y",
               std::vector<std::string>{"atan(50*(x + y - 1))", "0"},
               {});
  sim.set_cycle_callback([&](unsigned int) {
    history.emplace_back(sim.n_dofs(), sim.error_norm(u, false));
  });
  sim.run();
  return history;
}

// log-log interpolation of the error at `n` DoFs from a history.
double
error_at(const std::vector<std::pair<double, double>> &h, const double n)
{
  for (unsigned int i = 1; i < h.size(); ++i)
    if (h[i].first >= n)
      {
        const double s =
          std::log(n / h[i - 1].first) / std::log(h[i].first / h[i - 1].first);
        return std::exp((1 - s) * std::log(h[i - 1].second) +
                        s * std::log(h[i].second));
      }
  return h.back().second;
}

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  std::vector<std::pair<double, double>> uniform;
  for (unsigned int r = 2; r <= 6; ++r)
    {
      const auto p = parameters_from_string<forma::ElasticityParameters>(
        layer_problem(r, " set Degree = 2\n"));
      forma::ElasticitySimulator<2> sim(p, MPI_COMM_WORLD);
      sim.run();
      FunctionParser<2> u(2);
      u.initialize("x,y",
                   std::vector<std::string>{"atan(50*(x + y - 1))", "0"},
                   {});
      uniform.emplace_back(sim.n_dofs(), sim.error_norm(u, false));
    }
  const auto h  = study("h", 2, 8);
  const auto hp = study("hp", 2, 8);
  for (const auto &[name, hist] : std::vector<
         std::pair<std::string, std::vector<std::pair<double, double>>>>{
         {"uniform Q2", uniform}, {"h-adaptive Q2", h}, {"hp-adaptive", hp}})
    {
      deallog << name << ":";
      for (const auto &[n, e] : hist)
        deallog << " (" << n << ", " << rounded(e, 3) << ")";
      deallog << std::endl;
    }
  // Compare at the finest uniform mesh's DoF count (both adaptive runs
  // pass it).
  const double n = uniform.back().first;
  deallog << "at " << n << " DoFs: h-adaptive / uniform error < 0.5: "
          << (error_at(h, n) < 0.5 * uniform.back().second ? "yes" : "no")
          << ", hp-adaptive / uniform error < 0.5: "
          << (error_at(hp, n) < 0.5 * uniform.back().second ? "yes" : "no")
          << std::endl;
}
