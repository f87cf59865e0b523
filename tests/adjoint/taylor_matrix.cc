// Taylor tests of the adjoint gradient (thesis ch. 3.4-3.8) for every
// objective term against every design block: static linear and
// Neo-Hookean in 2D and 3D, transient BDF1 and BDF2 with damping, and the
// design regularizations (boundary and material smoothing, eqs. 3.43-3.44).
// Each line says "rate >= 1.9" when the error of J(q + eps theta) - J(q) - eps
// dJ.theta fell at least as eps^1.9 over the table (halving eps from 1e-2),
// "exact" when J is linear along theta (all errors at round-off), or the rates.
//
// The loads of every run: a traction on the right end, a pressure on the
// bottom, gravity; the left end is clamped.

#include <forma/elasticity/taylor_test.h>

#include "../tests.h"

using namespace dealii;

namespace
{
  struct Case
  {
    unsigned int dim;
    std::string  model, problem;
    unsigned int bdf;
  };

  std::string
  prm(const Case &c, const std::string &block, const std::string &terms)
  {
    const bool         d2      = c.dim == 2;
    const bool         dynamic = c.problem == "transient";
    std::ostringstream s;
    s << "subsection Mesh\n set Generator = subdivided_hyper_rectangle\n"
      << " set Generator arguments = "
      << (d2 ? "6, 2 : 0, 0 : 4, 1 : true" :
               "3, 1, 1 : 0, 0, 0 : 3, 1, 1 : true")
      << "\nend\nsubsection Finite element\n set Degree = 2\nend\n"
      << "subsection Material\n set Model = " << c.model
      << "\n set Bodies = * : E = 1e4, nu = 0.3, density = "
      << (dynamic ? 100 : 1) << ", damping shear = 20, damping bulk = 10\nend\n"
      << "subsection Boundary conditions\n set Dirichlet = 0 : "
      << (d2 ? "xy : 0, 0" : "xyz : 0, 0, 0")
      << "\n set Traction = 1 : " << (d2 ? "0, -10" : "0, -10, 5")
      << "\n set Pressure = 2 : 20\nend\n"
      << "subsection Loads\n set Gravity = "
      << (d2 ? "0, -9.81" : "0, 0, -9.81")
      << "\nend\nsubsection Time\n set Problem = " << c.problem
      << "\n set End time = 0.12\n set Time step = 0.04\n set BDF order = "
      << c.bdf << "\nend\nsubsection Initial conditions\n set Velocity = "
      << (d2 ? "0, 1" : "0, 0, 1") << "\nend\n"
      << "subsection Solver\n set Newton relative tolerance = 1e-12\n"
      << " set Newton absolute tolerance = 1e-14\nend\n"
      << "subsection Design\n set Parameters = " << block
      << "\n set Fixed boundaries = 0\nend\n"
      << "subsection Objective\n set Terms = " << terms << "\nend\n";
    return s.str();
  }

  template <int dim>
  void
  check(const Case &c, const std::string &block, const std::string &terms)
  {
    const auto p = parameters_from_string<forma::ElasticityParameters>(
      "set Dimension = " + std::to_string(dim) + "\n" + prm(c, block, terms));
    forma::ElasticitySimulator<dim> simulator(p, MPI_COMM_WORLD);
    simulator.prepare();
    simulator.set_objective(
      std::make_shared<const forma::Objective<dim>>(p.objective));
    forma::GradientCheckParameters gc;
    gc.n_steps    = 4;
    const auto  r = forma::taylor_test(simulator, gc);
    std::string verdict;
    if (std::isnan(r.min_rate))
      verdict = "exact";
    else if (r.min_rate >= 1.9)
      verdict = "rate >= 1.9";
    else
      {
        verdict = "FAILED, rates";
        for (const double x : r.rates)
          verdict += " " + std::to_string(x);
      }
    deallog << dim << "D " << c.model << ' ' << c.problem
            << (c.problem == "transient" ? " BDF" + std::to_string(c.bdf) : "")
            << " | " << block << " | " << terms << ": " << verdict << std::endl;
  }

  void
  run(const Case                     &c,
      const std::vector<std::string> &blocks,
      const std::vector<std::string> &terms)
  {
    for (const auto &b : blocks)
      for (const auto &t : terms)
        {
          // The L^p stress norm is not differentiable at zero stress, which
          // an initial-displacement perturbation from rest starts from.
          if (b.find("initial displacement") == 0 &&
              t.find("p=") != std::string::npos)
            continue;
          // Boundary smoothing (eq. 3.43) is a function of the shape only.
          if (t.find("boundary smoothing") == 0 && b != "shape")
            continue;
          if (c.dim == 2)
            check<2>(c, b, t);
          else
            check<3>(c, b, t);
        }
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const std::vector<std::string> all_terms     = {"stress : p=4",
                                                  "von mises : p=6",
                                                  "compliance",
                                                  "volume bound : bound=3",
                                                  "stress bound : bound=30",
                                                  "von mises bound : bound=30",
                                                  "target",
                                                  "boundary target : boundary=1",
                                                  "center of mass : x=2, y=0.4",
                                                  "height",
                                                  "boundary smoothing : p=2",
                                                  "material smoothing"};
  const std::vector<std::string> static_blocks = {"shape",
                                                  "cell material",
                                                  "material",
                                                  "loads"};
  for (const std::string model : {"linear elastic", "neo-hookean"})
    run({2, model, "static", 1}, static_blocks, all_terms);
  run({3, "neo-hookean", "static", 1},
      {"shape", "cell material", "loads"},
      {"von mises : p=4",
       "volume bound : bound=2",
       "boundary target : boundary=1",
       "center of mass : x=2, y=0.4, z=0.5",
       "boundary smoothing : p=3",
       "material smoothing"});
  for (const unsigned int bdf : {1u, 2u})
    run({2, "neo-hookean", "transient", bdf},
        {"shape",
         "material",
         "damping",
         "loads",
         "initial displacement",
         "initial velocity",
         "initial displacement field",
         "initial velocity field"},
        {"stress : p=4", "target", "center of mass : x=2, y=0.4"});
  run({2, "linear elastic", "transient", 2},
      {"cell material", "damping", "initial velocity"},
      {"target", "height"});
  run({3, "neo-hookean", "transient", 2},
      {"shape", "damping", "initial velocity"},
      {"target"});
}
