// Transient h adaptivity (Finite element/Adaptivity = h on a transient
// problem): the mesh is refined and coarsened during the run and every BDF
// history level moves to the new mesh.
//  - Exactness: a two-material bar stretched at a constant rate, u = t f(x)
//    with f piecewise linear (kink at the material interface, where Kelly
//    refines; coarsening elsewhere removes only linear pieces). Q1 holds u
//    on every mesh and BDF is exact for motions linear in time, so u_h = u
//    and v_h = f at every step if and only if all history levels are
//    carried over exactly: fixed BDF2 and variable-order adaptive BDF1-3.
//  - A wave pulse along a bar: the adaptive run follows the fronts and
//    matches the uniformly fine run (the finest level everywhere) at a
//    point, with fewer DoFs summed over the steps.

#include <deal.II/base/function_parser.h>

#include <forma/elasticity/simulator.h>

#include "../tests.h"

#include <algorithm>
#include <cmath>
#include <fstream>

using namespace dealii;

// Two materials: E = 1 on x < 0.5 (id 1), E = 4 on x > 0.5 (id 2); faces
// x = 0: 1, x = 1: 2, y = 0: 3, y = 0.25: 4.
void
write_bar_mesh(const std::string &file)
{
  std::ofstream m(file);
  m << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n10\n";
  for (unsigned int j = 0; j < 2; ++j)
    for (unsigned int i = 0; i < 5; ++i)
      m << 1 + i + 5 * j << " " << 0.25 * i << " " << 0.25 * j << " 0\n";
  m << "$EndNodes\n$Elements\n14\n";
  unsigned int e = 1;
  m << e++ << " 1 2 1 1 1 6\n" << e++ << " 1 2 2 2 5 10\n";
  for (unsigned int i = 0; i < 4; ++i)
    m << e++ << " 1 2 3 3 " << 1 + i << " " << 2 + i << "\n"
      << e++ << " 1 2 4 4 " << 6 + i << " " << 7 + i << "\n";
  for (unsigned int i = 0; i < 4; ++i)
    m << e++ << " 3 2 " << (i < 2 ? 1 : 2) << " 1 " << 1 + i << " " << 2 + i
      << " " << 7 + i << " " << 6 + i << "\n";
  m << "$EndElements\n";
}

// f(x): slope a1 on the soft half, a1 (lambda1 + 2 mu1) / (lambda2 + 2 mu2)
// = a1 / 4 on the stiff half (same nu): sigma_xx is continuous.
const std::string f_x = "(x < 0.5 ? 0.1 * x : 0.05 + 0.025 * (x - 0.5))";

std::string
stretched_bar(const std::string &time)
{
  return "subsection Mesh\n set Source = file\n set File = bar.msh\n"
         " set Initial refinement = 2\nend\n"
         "subsection Finite element\n set Adaptivity = h\n"
         " set Marking = error fraction\n set Refine fraction = 0.5\n"
         " set Coarsen fraction = 0.05\n set Adapt every = 2\n"
         " set Max refinement level = 2\n set Adaptive cycles = 1\nend\n"
         "subsection Material\n set Bodies = 1 : E = 1, nu = 0.3 ; "
         "2 : E = 4, nu = 0.3\nend\n"
         "subsection Boundary conditions\n set Dirichlet = 1 : xy : 0, 0 ; "
         "2 : xy : 0.0625 * t, 0 ; 3 : y : 0 ; 4 : y : 0\nend\n"
         "subsection Initial conditions\n set Velocity = " +
         f_x + ", 0\nend\n" +
         "subsection Solver\n set Linear solver = direct\n"
         " set Newton relative tolerance = 1e-13\nend\n" +
         "subsection Time\n set Problem = transient\n set End time = 1\n" +
         time + "end\n";
}

void
exactness(const std::string &name, const std::string &time)
{
  const auto p =
    parameters_from_string<forma::ElasticityParameters>(stretched_bar(time));
  forma::ElasticitySimulator<2> sim(p, MPI_COMM_WORLD);
  sim.run();
  FunctionParser<2> exact(2);
  exact.initialize("x,y", std::vector<std::string>{f_x, "0"}, {});
  // Kinetic energy of v = f: rho / 2 * 0.25 * int_0^1 f^2 dx.
  const double kinetic =
    0.125 * (0.01 / 24 + (std::pow(0.0625, 3) - std::pow(0.05, 3)) / 0.075);
  double worst = 0;
  for (const auto &s : sim.steps())
    worst = std::max(worst, std::abs(s.kinetic_energy - kinetic) / kinetic);
  unsigned long long fewest = sim.steps()[0].n_dofs, most = fewest;
  for (const auto &s : sim.steps())
    {
      fewest = std::min(fewest, s.n_dofs);
      most   = std::max(most, s.n_dofs);
    }
  const auto summary = sim.summary();
  deallog << name << ": " << sim.steps().size() - 1 << " steps, "
          << summary["mesh_adaptation"]["adaptations"].get<unsigned int>()
          << " adaptations, DoFs " << fewest << " to " << most << std::endl;
  check("the mesh changed", fewest < most);
  check("u_h = t f at the end (L2 error < 1e-11)",
        sim.error_norm(exact, false) < 1e-11);
  check("kinetic energy of v = f at every step (rel. error < 1e-10)",
        worst < 1e-10);
}

// A longitudinal pulse enters a bar [0, 8] x [0, 1] at x = 0 and runs to
// the clamped end; the step records and the summary.
std::pair<std::vector<forma::ElasticitySimulator<2>::StepRecord>,
          nlohmann::json>
pulse(const unsigned int refinement, const std::string &adaptivity)
{
  const auto p = parameters_from_string<forma::ElasticityParameters>(
    "subsection Mesh\n set Generator = subdivided_hyper_rectangle\n"
    " set Generator arguments = 16, 2 : 0, 0 : 8, 1 : true\n"
    " set Initial refinement = " +
    std::to_string(refinement) +
    "\nend\n"
    "subsection Finite element\n set Degree = 2\n" +
    adaptivity +
    "end\n"
    "subsection Material\n set Bodies = * : E = 1e4, nu = 0.3\nend\n"
    "subsection Boundary conditions\n set Dirichlet = 1 : xy : 0, 0\n"
    " set Traction = 0 : 100 * exp(-((t - 0.012) / 0.004)^2), 0\nend\n"
    "subsection Time\n set Problem = transient\n set End time = 0.06\n"
    " set Time step = 0.0005\nend\n"
    "subsection Output\n set Points = 4, 0.5\nend\n");
  forma::ElasticitySimulator<2> sim(p, MPI_COMM_WORLD);
  sim.run();
  return {sim.steps(), sim.summary()};
}

void
wave_pulse()
{
  const auto [fine, f] = pulse(2, "");
  const auto [adaptive, a] =
    pulse(0,
          " set Adaptivity = h\n set Marking = error fraction\n"
          " set Refine fraction = 0.8\n set Coarsen fraction = 0.05\n"
          " set Adapt every = 4\n set Max refinement level = 2\n");
  double difference = 0, peak = 0;
  for (unsigned int k = 0; k < fine.size(); ++k)
    {
      const double x = fine[k].point_displacements[0][0];
      const double y = adaptive[k].point_displacements[0][0];
      difference     = std::max(difference, std::abs(x - y));
      peak           = std::max(peak, std::abs(x));
    }
  unsigned long long fine_cost = 0;
  for (std::size_t k = 1; k < fine.size(); ++k)
    fine_cost += fine[k].n_dofs;
  const double ratio =
    double(a["mesh_adaptation"]["dof_steps"].get<unsigned long long>()) /
    fine_cost;
  deallog << "wave pulse: peak u_x(4, 0.5) " << rounded(peak, 3)
          << ", adaptive - fine max " << rounded(difference / peak, 2)
          << " of it, DoF-steps adaptive / fine " << rounded(ratio, 2)
          << std::endl;
  check("adaptive within 2% of the peak", difference < 0.02 * peak);
  check("fewer DoF-steps than the fine run", ratio < 0.7);
}

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    {
      initlog();
      write_bar_mesh("bar.msh");
    }
  MPI_Barrier(MPI_COMM_WORLD);
  exactness("BDF2, fixed steps", " set Time step = 0.1\n set BDF order = 2\n");
  exactness("BDF1-3, adaptive steps",
            " set Time step = 0.05\n set Integrator = adaptive\n"
            " set BDF order = 3\n set Variable order = true\n");
  wave_pulse();
}
