// The coverage polygon D(alpha) (thesis Fig. 4.13): the fit on a
// staircase coverage whose best polygon is known; on the shipped map, the
// polygon is inscribed in the covered nodes at the construction's angles,
// points beyond the grid lie outside, its coefficients are monotone
// splines in the angle (no overshoot between construction angles), a
// sample on another branch of solutions is found and dropped, and the
// base's Poisson's ratio shears it (eq. 4.11); the angles two-scale design
// clamps to are those of D; the soft coverage constraint of two-scale
// design passes its Taylor test. The wide map's D, two polygons in (log E,
// nu): inscribed, holding auxetic and stiff materials at 90 degrees, its
// projection the closest point in (log E, nu - 0.3 E) for a sheared base,
// its penalty Taylor-tested through the log and the shear.

#include <forma/rhombic/material_map.h>

#include "../tests.h"

#include <algorithm>
#include <cmath>

using namespace dealii;
using namespace forma::rhombic;

namespace
{
  unsigned int
  n_half_planes(const CoverageRegion &region)
  {
    unsigned int n = 0;
    for (const auto &p : region.pieces())
      n += p.size();
    return n;
  }


  // On a logarithmic coverage axis with a sheared base (nu 0.3): points of
  // the wide map's D(90) far apart in E, the projection's optimality (no
  // point of the region on a fine grid in (log E, nu - 0.3 E) is closer to
  // the projected point than its projection), and the penalty's Taylor
  // test (the chain rule through log E and the shear).
  void
  log_coverage_checks(const MaterialMap &wide)
  {
    const CoverageRegion D = wide.coverage(90, 0);
    deallog << "  D(90): (0.015, -0.25) inside: "
            << (D.contains({{0.015, -0.25}}) ? "yes" : "no")
            << ", (0.015, 0.65): "
            << (D.contains({{0.015, 0.65}}) ? "yes" : "no")
            << ", (0.1, 0.35): " << (D.contains({{0.1, 0.35}}) ? "yes" : "no")
            << ", (0.3, 0.3): " << (D.contains({{0.3, 0.3}}) ? "yes" : "no")
            << std::endl;
    const CoverageRegion sheared = wide.coverage(80, 0.3);
    unsigned int         worse = 0, n = 0;
    for (const std::array<double, 2> m : {std::array<double, 2>{{0.3, -0.2}},
                                          std::array<double, 2>{{0.005, 0.9}},
                                          std::array<double, 2>{{0.2, 0.9}}})
      {
        const auto   q  = sheared.closest_point(m);
        const auto   wm = sheared.coordinates(m), wq = sheared.coordinates(q);
        const double d = std::hypot(wq[0] - wm[0], wq[1] - wm[1]);
        deallog << "  base nu 0.3, 80 degrees: (" << m[0] << ", " << m[1]
                << ") -> (" << q[0] << ", " << q[1] << "), "
                << (sheared.violation(q) <= 1e-12 ? "in" : "NOT in")
                << " the region" << std::endl;
        for (double x = std::log(0.005); x < std::log(0.4); x += 0.01)
          for (double y = -0.5; y < 1; y += 0.002, ++n)
            if (sheared.violation(sheared.material({{x, y}})) <= 0 &&
                std::hypot(x - wm[0], y - wm[1]) < d - 1e-12)
              ++worse;
      }
    deallog << "  grid points of the region closer than the projection: "
            << worse << (n > 100000 ? "" : " (too few tried)") << std::endl;
    const std::array<double, 2> m = {{0.25, 0.6}}, d = {{0.05, -0.4}};
    std::array<double, 2>       g  = {{0, 0}};
    const double                P0 = sheared.penalty(m, 0.01, g);
    deallog << "  penalty at (0.25, 0.6): " << P0 << std::endl;
    std::vector<double> errors;
    for (const double eps : {1e-3, 5e-4, 2.5e-4, 1.25e-4})
      {
        std::array<double, 2> unused = {{0, 0}};
        const double          P =
          sheared.penalty({{m[0] + eps * d[0], m[1] + eps * d[1]}},
                          0.01,
                          unused);
        errors.push_back(std::abs(P - P0 - eps * (g[0] * d[0] + g[1] * d[1])));
      }
    for (unsigned int k = 1; k < errors.size(); ++k)
      deallog << "  penalty Taylor rate "
              << rate_verdict(std::log(errors[k - 1] / errors[k]) /
                              std::log(2.))
              << std::endl;
  }

  // Two pieces on a T-shaped coverage of a 6 x 6 grid (a wide base of rows
  // 0-2, a narrow column of rows 3-5 at nu nodes 2-3): one polygon holds
  // the base or part of both; two hold everything.
  void
  two_piece_fit()
  {
    const std::vector<double> grid = {0, 0.1, 0.2, 0.3, 0.4, 0.5};
    std::vector<bool>         covered(36, false);
    for (unsigned int i = 0; i < 6; ++i)
      for (unsigned int j = 0; j < 6; ++j)
        covered[i * 6 + j] = i <= 2 || (j == 2 || j == 3);
    const auto one  = fit_coverage_pieces(grid, grid, covered, 0, 1);
    const auto two  = fit_coverage_pieces(grid, grid, covered, 0, 2);
    const auto held = [&](const std::vector<CoveragePolygon> &pieces,
                          bool                               &inscribed) {
      unsigned int n = 0;
      inscribed      = true;
      for (unsigned int i = 0; i < 6; ++i)
        for (unsigned int j = 0; j < 6; ++j)
          {
            bool in = false;
            for (const auto &p : pieces)
              {
                bool inside = p.E_min < p.E_max;
                for (const auto &h : p.half_planes())
                  inside =
                    inside && h[0] * grid[i] + h[1] * grid[j] <= h[2] + 1e-9;
                in = in || inside;
              }
            n += in && covered[i * 6 + j];
            inscribed = inscribed && (!in || covered[i * 6 + j]);
          }
      return n;
    };
    bool       inscribed_one, inscribed_two;
    const auto n_one = held(one, inscribed_one);
    const auto n_two = held(two, inscribed_two);
    deallog << "T-shaped coverage (24 nodes): one polygon holds " << n_one
            << (inscribed_one ? "" : " (NOT inscribed)") << ", two hold "
            << n_two << (inscribed_two ? "" : " (NOT inscribed)")
            << "; split at E = " << two[0].E_max << " = " << two[1].E_min
            << "; areas " << one[0].area(0.5) << " -> "
            << two[0].area(0.5) + two[1].area(0.5) << std::endl;
  }
} // namespace



int
main()
{
  initlog();
  const MaterialMap map = MaterialMap::read(std::string(FORMA_SOURCE_DIR) +
                                            "/contrib/rhombic/map.json");
  const auto        violation =
    [](const CoverageRegion &region, const double E, const double nu) {
      return region.violation({{E, nu}});
    };
  // A staircase coverage on a 6 x 6 grid: row i starts at node 3 - i (the
  // boundary points lie on one line) and ends at node 5, except row 5,
  // which ends at node 3. Best polygon: the whole E range, nu_min = 0,
  // s_l through the staircase (nu = 0.3 - E), nu_max = 0.5 and s_r
  // through (nu, E) = (0.3, 0.5) at the steepest slope allowed (twice the
  // grid's diagonal: nu = 1.3 at E = 0), which loses the least; area
  // 1 - 0.045 / 0.25 - 0.01 / 0.25 = 0.78 of the grid.
  {
    const std::vector<double> grid = {0, 0.1, 0.2, 0.3, 0.4, 0.5};
    std::vector<bool>         covered(36, false);
    for (unsigned int i = 0; i < 6; ++i)
      for (unsigned int j = (i < 3 ? 3 - i : 0); j < (i == 5 ? 4 : 6); ++j)
        covered[i * 6 + j] = true;
    const auto P = fit_coverage_polygon(grid, grid, covered, 0);
    deallog << "staircase:";
    for (const double c : P.coefficients())
      deallog << ' ' << c;
    deallog << ", area " << P.area(0.5) << std::endl;
    deallog << "  outline (nu, E):";
    for (const auto &x : P.outline())
      deallog << " (" << x[0] << ", " << x[1] << ')';
    deallog << std::endl;
  }

  // Every row of the polygon at a construction angle lies in the covered
  // run of that row (the polygon is inscribed), for the shipped map and
  // the full-size one.
  const auto inscribed = [&](const MaterialMap &m) {
    for (unsigned int a = 0; a < m.angles.size(); ++a)
      {
        const auto   region = m.coverage(m.angles[a], 0);
        double       worst  = -1e300;
        unsigned int n = 0, inside = 0;
        for (unsigned int i = 0; i < m.E.size(); ++i)
          for (unsigned int j = 0; j < m.nu.size(); ++j)
            {
              const bool   c = m.covered[a][i * m.nu.size() + j];
              const double v = violation(region, m.E[i], m.nu[j]);
              n += c;
              inside += c && !region.empty() && v <= 1e-6;
              if (!c)
                worst = std::max(worst, -v); // > 0: an uncovered node inside
            }
        deallog << "angle " << m.angles[a] << ": " << n_half_planes(region)
                << " half-planes, " << inside << " of " << n
                << " covered nodes inside"
                << (region.empty() ? " (no region)" :
                    worst < 1e-6   ? ", no uncovered node inside" :
                                     ", an uncovered node inside!")
                << std::endl;
        if (!region.empty())
          deallog << "  E/E_b = 0.2 inside: "
                  << (violation(region, 0.2, 0.2) <= 0 ? "yes" : "no")
                  << ", nu = -0.3 inside: "
                  << (violation(region, 0.05, -0.3) <= 0 ? "yes" : "no")
                  << std::endl;
      }
  };
  inscribed(map);
  deallog << "full-size map:" << std::endl;
  inscribed(MaterialMap::read(std::string(FORMA_SOURCE_DIR) +
                              "/contrib/rhombic/map_full.json"));
  // The wide map's polygons are convex in (log E, nu): inscribed on that
  // axis, and at 90 degrees holding auxetic and stiff materials.
  const MaterialMap wide = MaterialMap::read(std::string(FORMA_SOURCE_DIR) +
                                             "/contrib/rhombic/map_wide.json");
  deallog << "wide map, coverage axis " << (wide.log_coverage ? "log E" : "E")
          << ':' << std::endl;
  inscribed(wide);
  log_coverage_checks(wide);
  two_piece_fit();
  // Format 3 written and read back: the same region at and between the
  // construction angles.
  {
    wide.write("wide_copy.json");
    const MaterialMap copy = MaterialMap::read("wide_copy.json");
    unsigned int      same = 0, n = 0;
    for (double a = 60; a <= 90; a += 1.25)
      for (const std::array<double, 2> m : {std::array<double, 2>{{0.02, -0.2}},
                                            std::array<double, 2>{{0.2, 0.3}},
                                            std::array<double, 2>{{0.05, 0.5}}})
        {
          ++n;
          same += std::abs(copy.coverage(a, 0.1).violation(m) -
                           wide.coverage(a, 0.1).violation(m)) < 1e-12;
        }
    deallog << "  format 3 read back: " << same << " of " << n
            << " violations the same, " << copy.polygons.size()
            << " pieces, log axis " << copy.log_coverage << std::endl;
  }
  deallog << "polygon coefficients over the angle (E_min, E_max, nu_min, "
             "nu_max, s_l at E_0, E_1, s_r at E_0, E_1):"
          << std::endl;
  for (double alpha = 90; alpha >= 59.9; alpha -= 7.5)
    {
      const auto region = map.coverage(alpha, 0);
      deallog << "  " << alpha << ": " << n_half_planes(region)
              << " half-planes, "
              << "(0.06, 0.2) inside: "
              << (violation(region, 0.06, 0.2) <= 1e-6 ? "yes" : "no")
              << std::endl;
    }
  for (unsigned int k = 0; k < CoveragePolygon::n_coefficients; ++k)
    {
      deallog << "  coefficient " << k << ':';
      for (double alpha = 90; alpha >= 59.9; alpha -= 7.5)
        deallog << ' ' << map.coverage_polygon(alpha).coefficients()[k];
      deallog << std::endl;
    }

  // Between two construction angles every coefficient of the full-size
  // map's polygon stays between its values there (monotone splines: the
  // polygons change abruptly from one angle to the next, a fitted cubic
  // overshoots both).
  {
    const MaterialMap full = MaterialMap::read(
      std::string(FORMA_SOURCE_DIR) + "/contrib/rhombic/map_full.json");
    const auto  &a       = full.polygon_splines[0].angles;
    const auto  &values  = full.polygon_splines[0].values;
    unsigned int outside = 0, n = 0;
    for (unsigned int i = 0; i + 1 < a.size(); ++i)
      for (double t = 0.05; t < 1; t += 0.1, ++n)
        {
          const auto c =
            full.coverage_polygon(a[i] + t * (a[i + 1] - a[i])).coefficients();
          for (unsigned int k = 0; k < c.size(); ++k)
            outside +=
              c[k] < std::min(values[k][i], values[k][i + 1]) - 1e-12 ||
              c[k] > std::max(values[k][i], values[k][i + 1]) + 1e-12;
        }
    deallog << "full-size map, " << n << " angles between construction "
            << "angles: " << outside
            << " coefficients outside their neighbours' range" << std::endl;
    // Two-scale design clamps the quads' angles to covered_angles(): D is
    // not empty there, and empty just below (47.5 degrees has covered
    // nodes but too few for a polygon).
    const auto range = full.covered_angles();
    deallog << "full-size map: covered angles " << range[0] << "-" << range[1]
            << ", D at " << range[0] << ": "
            << n_half_planes(full.coverage(range[0], 0)) << " half-planes, at "
            << range[0] - 0.5 << ": "
            << n_half_planes(full.coverage(range[0] - 0.5, 0)) << std::endl;
  }

  // Samples on another branch of solutions (thesis ch. 4.6.3's continuation
  // can jump): none in the full-size map; one moved onto the branch that
  // the rebuild below 60 degrees met (p2 = 0.49, p4 = 0.13) is dropped, and
  // its node uncovered.
  {
    MaterialMap full = MaterialMap::read(std::string(FORMA_SOURCE_DIR) +
                                         "/contrib/rhombic/map_full.json");
    const auto  n    = full.samples.size();
    deallog << "branch jumps in the full-size map: "
            << full.drop_branch_jumps(0.25) << std::endl;
    auto &s      = full.samples[n / 2];
    s[4]         = 0.49;
    s[6]         = 0.13;
    const auto a = std::find(full.angles.begin(), full.angles.end(), s[2]) -
                   full.angles.begin();
    const auto i = std::lround((s[0] - full.E[0]) / (full.E[1] - full.E[0]));
    const auto j = std::lround((s[1] - full.nu[0]) / (full.nu[1] - full.nu[0]));
    deallog << "one sample moved to the other branch: "
            << full.drop_branch_jumps(0.25) << " dropped, "
            << full.samples.size() << " of " << n << " left, its node "
            << (full.covered[a][i * full.nu.size() + j] ? "covered" :
                                                          "uncovered")
            << std::endl;
  }

  // A base with nu = 0.3: the node (E, nu_map) moves to nu = nu_map + 0.3 E.
  {
    const auto region = map.coverage(90, 0.3);
    deallog << "base nu 0.3, node (0.1, 0.4) at nu = 0.43: "
            << (violation(region, 0.1, 0.43) <= 1e-6 ? "inside" : "outside")
            << ", at nu = 0.44: "
            << (violation(region, 0.1, 0.44) <= 1e-6 ? "inside" : "outside")
            << ", at nu = 0.02 (0.03 is the lowest): "
            << (violation(region, 0.1, 0.02) <= 1e-6 ? "inside" : "outside")
            << std::endl;
  }

  // Taylor test of the penalty at a point outside (one smooth piece).
  const auto                  region = map.coverage(75, 0);
  const std::array<double, 2> m = {{0.115, 0.43}}, d = {{0.3, -0.7}};
  std::array<double, 2>       g  = {{0, 0}};
  const double                P0 = region.penalty(m, 0.01, g);
  deallog << "penalty at (0.115, 0.43): " << P0 << std::endl;
  double previous = 0;
  for (const double eps : {1e-3, 5e-4, 2.5e-4, 1.25e-4})
    {
      std::array<double, 2> unused = {{0, 0}};
      const double          P =
        region.penalty({{m[0] + eps * d[0], m[1] + eps * d[1]}}, 0.01, unused);
      const double error = std::abs(P - P0 - eps * (g[0] * d[0] + g[1] * d[1]));
      if (previous > 0)
        deallog << "  eps " << eps << ": rate "
                << std::log(previous / error) / std::log(2.) << std::endl;
      previous = error;
    }
}
