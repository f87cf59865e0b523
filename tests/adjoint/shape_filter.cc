// Design/Shape filter radius (adjoint/shape_filter.h, vertex morphing): the
// shape design is a control field whose filtered values move the vertices.
// - A uniform control moves the vertices by at most its value (the weights
//   sum to one; far from the clamped side exactly by it);
// - one entry moves its vertex by less than the entry, and its
//   neighbours within the radius too (the move is spread);
// - the start is Design/Shape perturbation, filter or not;
// - the chained gradient A^T dJ/dx passes the Taylor test, with every
//   vertex a design variable and with boundary shape parameters (harmonic
//   interior), 2D quads with two materials and 3D tetrahedra.

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_out.h>
#include <deal.II/grid/tria.h>

#include "../tests.h"
#include "shape_tests.h"

#include <filesystem>

using namespace dealii;

namespace
{
  std::string
  strip(const std::string &parameterization,
        const double       radius,
        const bool         perturbed = true)
  {
    return "set Dimension = 2\n"
           "subsection Mesh\n set Generator = subdivided_hyper_rectangle\n"
           " set Generator arguments = 24, 8 : 0, 0 : 3, 1 : true\nend\n"
           "subsection Finite element\n set Degree = 2\nend\n"
           "subsection Material\n set Bodies = * : E = 1e4, nu = 0.3\nend\n"
           "subsection Boundary conditions\n set Dirichlet = 0 : xy : 0, 0\n"
           " set Traction = 1 : 0, -50\nend\n"
           "subsection Solver\n set Newton relative tolerance = 1e-12\n"
           " set Newton absolute tolerance = 1e-14\nend\n"
           "subsection Design\n set Parameters = shape\n"
           " set Fixed boundaries = 0\n set Shape parameterization = " +
           parameterization +
           "\n set Shape filter radius = " + std::to_string(radius) +
           (perturbed ? "\n set Shape perturbation = 0.05 * sin(pi * x / 3) * "
                        "y, 0.03 * x * y" :
                        "") +
           "\nend\n"
           "subsection Objective\n set Terms = stress : p=4 ; volume\nend\n";
  }

  void
  moves()
  {
    const auto p = parameters_from_string<forma::ElasticityParameters>(
      strip("vertices", 0.3, false));
    forma::ElasticitySimulator<2> s(p, MPI_COMM_WORLD);
    s.prepare();
    s.set_objective(std::make_shared<const forma::Objective<2>>(p.objective));
    const unsigned int n = s.design().size();

    s.set_design(std::vector<double>(n, 0.01));
    deallog << "2D: uniform control 0.01: largest vertex move "
            << rounded(s.max_shape_offset(), 6) << std::endl;

    // An entry of a free vertex (a clamped one's moves nothing itself).
    double one = 0;
    for (unsigned int i = n / 2; i < n && one == 0; ++i)
      {
        std::vector<double> spike(n, 0.);
        spike[i] = 0.01;
        s.set_design(spike);
        one = s.max_shape_offset();
      }
    check("one entry of 0.01 moves its vertex by less (spread)",
          one > 0 && one < 0.01);
  }

  // The start is Design/Shape perturbation as given, with or without the
  // filter.
  void
  start()
  {
    double offset[2];
    for (const double r : {0., 0.3})
      {
        const auto p = parameters_from_string<forma::ElasticityParameters>(
          strip("vertices", r));
        forma::ElasticitySimulator<2> s(p, MPI_COMM_WORLD);
        s.prepare();
        s.set_design(s.design());
        offset[r > 0] = s.max_shape_offset();
      }
    check("the filtered start is the perturbation",
          std::abs(offset[1] - offset[0]) < 1e-12 && offset[0] > 0);
  }

  void
  gradients_2d(const std::string &parameterization)
  {
    const auto p = parameters_from_string<forma::ElasticityParameters>(
      strip(parameterization, 0.3));
    forma::ElasticitySimulator<2> s(p, MPI_COMM_WORLD);
    s.prepare();
    s.set_objective(std::make_shared<const forma::Objective<2>>(p.objective));
    deallog << "2D, " << parameterization
            << ", radius 0.3: " << taylor_verdict(s) << std::endl;
  }

  void
  gradients_3d()
  {
    const auto p = parameters_from_string<forma::ElasticityParameters>(
      tetrahedral_bar(" set Shape parameterization = boundary\n"
                      " set Shape filter radius = 0.5\n",
                      "compliance; volume"));
    forma::ElasticitySimulator<3> s(p, MPI_COMM_WORLD);
    s.prepare();
    s.set_objective(std::make_shared<const forma::Objective<3>>(p.objective));
    deallog << "3D tetrahedra, boundary, radius 0.5: " << taylor_verdict(s)
            << std::endl;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
    initlog();
  moves();
  start();
  gradients_2d("vertices");
  gradients_2d("boundary");
  gradients_3d();
}
