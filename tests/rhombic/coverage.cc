// The covered region D(alpha) of the shipped material-to-geometry map as
// half-planes: every covered node lies inside, points beyond the grid lie
// outside, and the base's Poisson's ratio shears the region (eq. 4.11);
// the soft coverage constraint of two-scale design passes its Taylor test.

#include <forma/rhombic/material_map.h>

#include "../tests.h"

using namespace dealii;
using namespace forma::rhombic;

int
main()
{
  initlog();
  const MaterialMap map = MaterialMap::read(std::string(FORMA_SOURCE_DIR) +
                                            "/contrib/rhombic/map.json");
  const auto violation  = [](const std::vector<MaterialMap::HalfPlane> &region,
                            const double                               E,
                            const double                               nu) {
    double v = -1e300;
    for (const auto &h : region)
      v = std::max(v, h.c_E * E + h.c_nu * nu - h.d);
    return v;
  };
  for (unsigned int a = 0; a < map.angles.size(); ++a)
    {
      const auto   region = map.coverage(map.angles[a], 0);
      double       worst  = -1e300;
      unsigned int n      = 0;
      for (unsigned int i = 0; i < map.E.size(); ++i)
        for (unsigned int j = 0; j < map.nu.size(); ++j)
          if (map.covered[a][i * map.nu.size() + j])
            {
              worst = std::max(worst, violation(region, map.E[i], map.nu[j]));
              ++n;
            }
      deallog << "angle " << map.angles[a] << ": " << region.size()
              << " half-planes, " << n << " covered nodes"
              << (region.empty() ? " (no region)" :
                  worst <= 1e-12 ? ", all inside" :
                                   ", one outside!")
              << std::endl;
      if (!region.empty())
        deallog << "  E/E_b = 0.2 inside: "
                << (violation(region, 0.2, 0.2) <= 0 ? "yes" : "no")
                << ", nu = -0.3 inside: "
                << (violation(region, 0.05, -0.3) <= 0 ? "yes" : "no")
                << std::endl;
    }
  // A base with nu = 0.3: the node (E, nu_map) moves to nu = nu_map + 0.3 E.
  {
    const auto region = map.coverage(90, 0.3);
    deallog << "base nu 0.3, node (0.1, 0.4) at nu = 0.43: "
            << (violation(region, 0.1, 0.43) <= 1e-12 ? "inside" : "outside")
            << ", at nu = 0.44: "
            << (violation(region, 0.1, 0.44) <= 1e-12 ? "inside" : "outside")
            << ", at nu = 0.02 (0.03 is the lowest): "
            << (violation(region, 0.1, 0.02) <= 1e-12 ? "inside" : "outside")
            << std::endl;
  }

  // Taylor test of the penalty at a point outside (one smooth piece).
  const auto                  region = map.coverage(75, 0);
  const std::array<double, 2> m = {{0.115, 0.43}}, d = {{0.3, -0.7}};
  std::array<double, 2>       g  = {{0, 0}};
  const double                P0 = coverage_penalty(m, region, 0.01, g);
  deallog << "penalty at (0.115, 0.43): " << P0 << std::endl;
  double previous = 0;
  for (const double eps : {1e-3, 5e-4, 2.5e-4, 1.25e-4})
    {
      std::array<double, 2> unused = {{0, 0}};
      const double          P      = coverage_penalty(
        {{m[0] + eps * d[0], m[1] + eps * d[1]}}, region, 0.01, unused);
      const double error = std::abs(P - P0 - eps * (g[0] * d[0] + g[1] * d[1]));
      if (previous > 0)
        deallog << "  eps " << eps << ": rate "
                << std::log(previous / error) / std::log(2.) << std::endl;
      previous = error;
    }
}
