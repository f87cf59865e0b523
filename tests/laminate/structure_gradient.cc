// Exact gradients of homogenized laminate structures (thesis ch. 5.4):
// E and nu of C^H on the rasterized grid as functions of the continuous
// structure parameters (p1, p2, p4 or p1, theta, alpha), differentiated by
// AD through the polygons, their exact pixel areas, the laminate phases and
// the Hashin-Shtrikman gray pixels, and C^H's self-adjoint material
// gradient. Taylor test: |f(q + h d) - f(q) - h f'(q) d| must fall as h^2
// (rates in [1.8, 2.3]; 1.9-2.1 measured),
// for a finite Hexagon and Triangle structure (chiral beams) and a limit
// Hexagon structure, on the symmetric half cell the inverse mode uses.

#include <forma/laminate/study.h>

#include "../tests.h"

#include <cmath>
#include <iomanip>

using namespace dealii;
using namespace forma;

namespace
{
  struct Values
  {
    double E, nu;
  };

  Values
  moduli(PeriodicHomogenization<2> &cell,
         const HexagonalLaminate   &s,
         const laminate::Setup     &setup,
         const unsigned int         nx,
         const unsigned int         ny,
         laminate::Sample          *sample = nullptr)
  {
    const auto r = laminate::evaluate(
      cell,
      pixel_material(s, setup.base, setup.weak, setup.gray, nx, ny),
      setup);
    if (sample)
      *sample = r;
    return {r.fit.E, r.fit.nu};
  }

  void
  taylor(const std::string           &name,
         const HexagonalLaminate     &s,
         const std::array<double, 3> &direction,
         const laminate::Setup       &setup)
  {
    const unsigned int ny   = 24;
    const unsigned int nx   = laminate::grid_nx(ny);
    auto               cell = laminate::family_grid(MPI_COMM_SELF, setup, ny);
    laminate::Sample   sample;
    const Values       f0 = moduli(*cell, s, setup, nx, ny, &sample);
    const auto g = laminate::evaluate_gradient(*cell, s, setup, nx, ny, sample);
    double     dE = 0, dnu = 0;
    for (unsigned int m = 0; m < 3; ++m)
      {
        dE += g.E[m] * direction[m];
        dnu += g.nu[m] * direction[m];
      }
    deallog << name << ": E = " << f0.E << ", nu = " << f0.nu << std::endl;
    double previous_E = 0, previous_nu = 0;
    for (unsigned int k = 0; k < 4; ++k)
      {
        const double h = 1e-2 / std::pow(2., k);
        auto         q = s.continuous_parameters();
        for (unsigned int m = 0; m < 3; ++m)
          q[m] += h * direction[m];
        HexagonalLaminate t = s;
        t.set_continuous_parameters(q);
        const Values       f    = moduli(*cell, t, setup, nx, ny);
        const double       e_E  = std::abs(f.E - f0.E - h * dE);
        const double       e_nu = std::abs(f.nu - f0.nu - h * dnu);
        std::ostringstream line;
        line << "  h = " << std::setw(9) << h;
        if (k > 0)
          line << "  rate(E) " << rate_verdict(std::log2(previous_E / e_E))
               << ", rate(nu) " << rate_verdict(std::log2(previous_nu / e_nu));
        deallog << line.str() << std::endl;
        previous_E  = e_E;
        previous_nu = e_nu;
      }
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  deallog << std::setprecision(4);
  laminate::Setup setup;
  setup.base      = IsotropicModuli::from_young_poisson(1, 0.3);
  setup.weak      = IsotropicModuli::from_young_poisson(1e-6, 0.3);
  setup.write_vtu = false;

  HexagonalLaminate hexagon;
  hexagon.p1 = 0.71, hexagon.p2 = 0.4, hexagon.p3 = 0.5, hexagon.p4 = 0.63;
  taylor("hexagon", hexagon, {{0.3, -0.5, 0.4}}, setup);

  HexagonalLaminate triangle = hexagon;
  triangle.family            = HexagonalLaminate::Family::triangle;
  triangle.p2 = 0.7, triangle.p4 = 0.55;
  taylor("triangle", triangle, {{-0.2, 0.3, 0.5}}, setup);

  HexagonalLaminate limit;
  limit.limit = true, limit.p1 = 0.7, limit.theta = 0.9, limit.alpha = 0.1;
  taylor("limit hexagon", limit, {{0.2, -0.4, 0.6}}, setup);
}
