// Homogenization on parallelogram cells through the reference square
// (thesis ch. 4.5.2, eqs. 4.6-4.7), checked against exact results:
//  - a layered cell on sheared and rhombic parallelograms, layers along
//    either side: the route must give the exact rank-one laminate of the
//    physical layers (the grid follows the layers, so Q2 is exact);
//  - at alpha = 90 degrees the rhombic route is the square cell turned by
//    45 degrees (square-cell homogenization of the same mesh, rotated);
//  - transform() with F then F^-1 is the identity.

#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/parallelogram_cell.h>
#include <forma/homogenization/periodic_homogenization.h>

#include "../tests.h"

using namespace dealii;
using namespace forma;

namespace
{
  double
  relative_error(const SymmetricTensor<4, 2> &A, const SymmetricTensor<4, 2> &B)
  {
    return (A - B).norm() / B.norm();
  }

  void
  layered(const std::string &name, const Tensor<2, 2> &F)
  {
    const auto   a = IsotropicModuli::from_young_poisson(1.0, 0.3).tensor();
    const auto   b = IsotropicModuli::from_young_poisson(0.1, -0.2).tensor();
    const double theta = 0.375;
    const ParallelogramCell parallelogram(F);
    const auto              a_ref = parallelogram.to_reference(a),
               b_ref              = parallelogram.to_reference(b);
    PeriodicHomogenization<2>::SolverParameters sp;
    PeriodicHomogenization<2>                   cell(
      MPI_COMM_WORLD, Point<2>(1.0, 1.0), {{8, 8}}, sp, 2);
    for (const unsigned int side : {0u, 1u})
      {
        // Layers parallel to the side a_side: material a where the
        // reference coordinate across them is below theta.
        const auto C_ref =
          cell
            .homogenize([&](const Point<2> &x, const types::material_id) {
              return x[1 - side] < theta ? a_ref : b_ref;
            })
            .C;
        const double angle = std::atan2(F[1][side], F[0][side]);
        const auto   exact = rank_one_laminate(a, b, theta, angle);
        const auto   C     = parallelogram.from_reference(C_ref);
        deallog << name << ", layers along a" << side + 1 << " ("
                << rounded(angle * 180 / M_PI)
                << " degrees): |C - C_exact|/|C| "
                << (relative_error(C, exact) < 1e-9 ? "< 1e-9" : "TOO LARGE")
                << std::endl;
      }
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  const double alpha = M_PI / 3;
  layered("sheared (a1 = e1, a2 at 60 degrees)",
          Tensor<2, 2>({{1., std::cos(alpha)}, {0., std::sin(alpha)}}));
  layered("rhombus at 60 degrees, diagonals on the axes",
          Tensor<2, 2>({{std::cos(alpha / 2), std::cos(alpha / 2)},
                        {-std::sin(alpha / 2), std::sin(alpha / 2)}}));
  layered("general parallelogram", Tensor<2, 2>({{1.2, 0.4}, {-0.1, 0.9}}));

  // transform(transform(C, G), F) = C
  {
    const Tensor<2, 2> F({{1.2, 0.4}, {-0.1, 0.9}});
    const auto         C = from_voigt(
      VoigtMatrix({{3., 1., 0.2}, {1., 2., -0.1}, {0.2, -0.1, 0.7}}));
    deallog << "transform round trip: "
            << (relative_error(transform(transform(C, invert(F)), F), C) <
                    1e-14 ?
                  "exact" :
                  "WRONG")
            << std::endl;
  }

  // alpha = 90 degrees: the rhombus is the square turned by -45 degrees,
  // and the isotropic base tensor is unchanged by eq. 4.6.
  {
    const double            c = std::sqrt(0.5);
    const ParallelogramCell square(Tensor<2, 2>({{c, c}, {-c, c}}));
    const auto base = IsotropicModuli::from_young_poisson(1.0, 0.0).tensor();
    deallog << "alpha = 90: eq. 4.6 leaves the isotropic base unchanged: "
            << (relative_error(square.to_reference(base), base) < 1e-14 ?
                  "yes" :
                  "NO")
            << std::endl;
    PeriodicHomogenization<2>::SolverParameters sp;
    PeriodicHomogenization<2>                   cell(
      MPI_COMM_WORLD, Point<2>(1.0, 1.0), {{16, 16}}, sp, 1);
    // A lopsided structure: a disk off the center and a bar.
    const auto C_square =
      cell
        .homogenize([&](const Point<2> &x, const types::material_id) {
          const bool solid =
            x.distance(Point<2>(0.3, 0.6)) < 0.25 || (x[1] > 0.1 && x[1] < 0.3);
          return solid ? base : 1e-3 * base;
        })
        .C;
    const auto C = square.from_reference(C_square);
    deallog << "alpha = 90: route = square result turned by -45 degrees: "
            << (relative_error(C, rotate(C_square, -M_PI / 4)) < 1e-13 ? "yes" :
                                                                         "NO")
            << std::endl;
  }
}
