// Transient checks of the BDF time stepping (thesis eq. 3.12):
//  - free fall under gravity: the mass-weighted mean displacement against
//    -g t^2 / 2 converges at the integrator's order (BDF1: 1; BDF2: 2, its
//    BDF1 start step costs no order);
//  - a one-mode oscillator (one Q1 cell whose only free motion is the
//    symmetric vertical mode, omega^2 = 3 (lambda + 2 mu) / rho): the
//    energy history of the finite element run equals the scalar BDF recurrence
//    for that mode, and shows BDF1 dissipating much more than BDF2;
//  - strain-rate damping removes energy from the same oscillator.

#include <forma/elasticity/simulator.h>
#include <forma/physics/bdf.h>

#include "../tests.h"

using namespace dealii;

forma::ElasticitySimulator<2>
make(const std::string &prm)
{
  return forma::ElasticitySimulator<2>(
    parameters_from_string<forma::ElasticityParameters>(prm), MPI_COMM_WORLD);
}

void
free_fall(const unsigned int order)
{
  std::vector<double> dts, errors;
  for (const double dt : {0.1, 0.05, 0.025})
    {
      auto sim = make(
        "subsection Mesh\n set Generator = hyper_cube\n"
        " set Generator arguments = 0 : 1 : false\nend\n"
        "subsection Material\n set Bodies = * : E = 100, nu = 0.3, density = 2\nend\n"
        "subsection Loads\n set Gravity = 0, -10\nend\n"
        "subsection Time\n set Problem = transient\n set End time = 1\n"
        " set Time step = " +
        std::to_string(dt) + "\n set BDF order = " + std::to_string(order) +
        "\nend\n");
      sim.run();
      const double y = sim.steps().back().mean_displacement[1];
      dts.push_back(dt);
      errors.push_back(std::abs(y - (-5.)));
    }
  const auto rates = observed_rates(dts, errors);
  deallog << "free fall BDF" << order
          << ": error at t = 1 for dt = 0.1: " << rounded(errors[0], 4)
          << ", observed order " << rounded(rates.back(), 3) << std::endl;
}

// Energy history of the scalar oscillator m a'' + k a = 0 under BDF-m.
std::vector<double>
scalar_energies(const unsigned int order,
                const double       omega2,
                const double       dt,
                const unsigned int n,
                const double       m,
                const double       k)
{
  std::vector<double> a{0.}, v{1.}, e{0.5 * m};
  for (unsigned int i = 1; i <= n; ++i)
    {
      const auto   c   = forma::bdf_coefficients_at_step(order, i);
      const double bdt = c.beta * dt;
      double       ha = 0, hv = 0;
      for (unsigned int j = 1; j <= c.alpha.size(); ++j)
        {
          ha += c.alpha[j - 1] * a[i - j];
          hv += c.alpha[j - 1] * v[i - j];
        }
      // a + ha = bdt v ; v + hv = -bdt omega2 a
      const double ai = (-ha - bdt * hv) / (1 + bdt * bdt * omega2);
      a.push_back(ai);
      v.push_back((ai + ha) / bdt);
      e.push_back(0.5 * m * v.back() * v.back() + 0.5 * k * ai * ai);
    }
  return e;
}

void
oscillator(const unsigned int order, const std::string &damping)
{
  const double       lambda = 1, mu = 1, dt = 0.05;
  const unsigned int n = 40;
  auto               sim =
    make("subsection Mesh\n set Generator = hyper_cube\n"
         " set Generator arguments = 0 : 1 : true\nend\n"
         "subsection Material\n set Bodies = * : lambda = 1, mu = 1" +
         damping +
         "\nend\n"
         "subsection Boundary conditions\n"
         " set Dirichlet = 2 : xy : 0, 0 ; 0 : x : 0 ; 1 : x : 0\nend\n"
         "subsection Initial conditions\n set Velocity = 0, y\nend\n"
         "subsection Time\n set Problem = transient\n set End time = 2\n"
         " set Time step = 0.05\n set BDF order = " +
         std::to_string(order) + "\nend\n");
  sim.run();
  const double k = lambda + 2 * mu, m = 1. / 3;
  const auto   e    = scalar_energies(order, k / m, dt, n, m, k);
  double       diff = 0;
  for (unsigned int i = 0; i <= n; ++i)
    diff = std::max(diff,
                    std::abs(sim.steps()[i].kinetic_energy +
                             sim.steps()[i].elastic_energy - e[i]));
  const double ratio =
    (sim.steps()[n].kinetic_energy + sim.steps()[n].elastic_energy) /
    (sim.steps()[0].kinetic_energy + sim.steps()[0].elastic_energy);
  if (damping.empty())
    deallog << "oscillator BDF" << order
            << ": E(T)/E(0) = " << rounded(ratio, 4)
            << ", matches the scalar BDF recurrence to 1e-10: "
            << (diff < 1e-10 ? "yes" : "no") << std::endl;
  else
    deallog << "damped oscillator BDF" << order
            << ": E(T)/E(0) = " << rounded(ratio, 4) << std::endl;
}

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  free_fall(1);
  free_fall(2);
  free_fall(3);
  for (unsigned int order = 1; order <= 4; ++order)
    oscillator(order, "");
  oscillator(2, ", damping shear = 0.1, damping bulk = 0.05");
}
