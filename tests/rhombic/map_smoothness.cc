// The shipped material-to-geometry maps have bounded second differences
// (thesis ch. 4.6: smoothness is what makes the interpolation of sparse
// samples accurate). Per map and direction (E, nu, angle), the second
// difference of every parameter relative to its range over the map's
// samples (fixed parameters left out), largest over:
// - the samples, the continuation's inverse solutions, over three
//   consecutive covered nodes (unequal angle steps: p'' h1 h2). A solve on
//   another branch of solutions gives more than the parameter's range (the
//   control below);
// - the fitted splines over one step of the construction grid in E and nu
//   and 2.5 degrees in the angle, at points x with x and x +- step inside
//   D(alpha). Cubic B-splines are C^2 by construction; what is checked is
//   that the fit is bounded and, along E and nu, not rougher than its data.
// And the tileable map (p5 fixed, as in the thesis's V) keeps the joint
// radius p5 the same everywhere, so neighbouring cells of one size meet
// exactly.

#include <forma/rhombic/material_map.h>

#include "../tests.h"

#include <algorithm>
#include <cmath>
#include <map>

using namespace dealii;
using namespace forma::rhombic;
using forma::RhombicStructure;

namespace
{
  constexpr unsigned int n_p = forma::RhombicStructure::n_parameters;
  using Parameters           = std::array<double, n_p>;

  bool
  inside(const MaterialMap &m, const double E, const double nu, const double a)
  {
    return m.coverage(a, 0).contains({{E, nu}}, 1e-12);
  }

  Parameters
  spline(const MaterialMap &m, const double E, const double nu, const double a)
  {
    Parameters p;
    for (unsigned int i = 0; i < n_p; ++i)
      p[i] = m.parameters[i].value({E, nu, a});
    return p;
  }

  /// Each parameter's smallest and largest value over the samples.
  std::array<Parameters, 2>
  sample_bounds(const MaterialMap &m)
  {
    std::array<Parameters, 2> b;
    b[0].fill(1e300);
    b[1].fill(-1e300);
    for (const auto &s : m.samples)
      for (unsigned int i = 0; i < n_p; ++i)
        {
          b[0][i] = std::min(b[0][i], s[3 + i]);
          b[1][i] = std::max(b[1][i], s[3 + i]);
        }
    return b;
  }

  /// Each parameter's range (max - min) over the samples.
  Parameters
  sample_ranges(const MaterialMap &m)
  {
    const auto b = sample_bounds(m);
    Parameters range;
    for (unsigned int i = 0; i < n_p; ++i)
      range[i] = b[1][i] - b[0][i];
    return range;
  }

  /// The largest relative second difference and how many were measured.
  struct Measured
  {
    double       worst = 0;
    unsigned int n     = 0;
  };

  /// Over the samples along direction d (0: E, 1: nu, 2: angle).
  Measured
  samples_along(const MaterialMap &m,
                const unsigned int d,
                const Parameters  &range)
  {
    // Samples by (angle, E, nu) grid index.
    std::map<std::array<long, 3>, Parameters> at;
    for (const auto &s : m.samples)
      {
        const long a =
          std::find(m.angles.begin(), m.angles.end(), s[2]) - m.angles.begin();
        const long i = std::lround((s[0] - m.E[0]) / (m.E[1] - m.E[0]));
        const long j = std::lround((s[1] - m.nu[0]) / (m.nu[1] - m.nu[0]));
        AssertThrow(a < static_cast<long>(m.angles.size()) && i >= 0 &&
                      i < static_cast<long>(m.E.size()) && j >= 0 &&
                      j < static_cast<long>(m.nu.size()) &&
                      std::abs(m.E[i] - s[0]) < 1e-9 &&
                      std::abs(m.nu[j] - s[1]) < 1e-9,
                    ExcMessage("a sample off the map's grid"));
        Parameters p;
        std::copy(s.begin() + 3, s.end(), p.begin());
        AssertThrow(at.emplace(std::array<long, 3>{{a, i, j}}, p).second,
                    ExcMessage("two samples at one grid node"));
      }
    const unsigned int k     = (d == 2 ? 0 : d + 1);
    const auto         coord = [&](const long index) {
      return d == 0 ? m.E[index] : d == 1 ? m.nu[index] : m.angles[index];
    };
    Measured r;
    for (const auto &[key, p] : at)
      {
        auto lo = key, hi = key;
        --lo[k];
        ++hi[k];
        const auto l = at.find(lo), h = at.find(hi);
        if (l == at.end() || h == at.end())
          continue;
        const double h1 = std::abs(coord(key[k]) - coord(lo[k])),
                     h2 = std::abs(coord(hi[k]) - coord(key[k]));
        for (unsigned int i = 0; i < n_p; ++i)
          if (range[i] > 0)
            r.worst = std::max(r.worst,
                               std::abs(2 *
                                        ((h->second[i] - p[i]) / h2 -
                                         (p[i] - l->second[i]) / h1) /
                                        (h1 + h2)) *
                                 h1 * h2 / range[i]);
        ++r.n;
      }
    return r;
  }

  /// Over the splines along direction d, on a lattice of points x with x
  /// and x +- step inside D(alpha).
  Measured
  splines_along(const MaterialMap &m,
                const unsigned int d,
                const double       step,
                const Parameters  &range)
  {
    const auto   angles = m.covered_angles();
    const double dE     = (m.E.back() - m.E.front()) / 24,
                 dnu    = (m.nu.back() - m.nu.front()) / 24;
    Measured  r;
    const int n_a = std::lround((angles[1] - angles[0]) / 1.25);
    for (int ia = 0; ia <= n_a; ++ia)
      for (int iE = 0; iE <= 24; ++iE)
        for (int inu = 0; inu <= 24; ++inu)
          {
            const double a = angles[0] + ia * 1.25, E = m.E.front() + iE * dE,
                         nu          = m.nu.front() + inu * dnu;
            std::array<double, 3> lo = {{E, nu, a}}, hi = lo;
            lo[d] -= step;
            hi[d] += step;
            if (!inside(m, E, nu, a) || !inside(m, lo[0], lo[1], lo[2]) ||
                !inside(m, hi[0], hi[1], hi[2]))
              continue;
            const auto p  = spline(m, E, nu, a);
            const auto pl = spline(m, lo[0], lo[1], lo[2]);
            const auto ph = spline(m, hi[0], hi[1], hi[2]);
            for (unsigned int i = 0; i < n_p; ++i)
              if (range[i] > 0)
                r.worst =
                  std::max(r.worst,
                           std::abs(pl[i] - 2 * p[i] + ph[i]) / range[i]);
            ++r.n;
          }
    return r;
  }

  void
  check(const std::string &name)
  {
    const MaterialMap m     = MaterialMap::read(std::string(FORMA_SOURCE_DIR) +
                                            "/contrib/rhombic/" + name);
    const Parameters  range = sample_ranges(m);
    // query() hands out the splines' structures at every sample, the node
    // positions p1..p4 clamped to the samples' range and node 4 kept clear
    // of the cell's corner, close to the sample's own parameters (the fit
    // residual; a clamp tighter than the samples would move them).
    const auto   bounds = sample_bounds(m);
    double       moved = 0, residual = 0;
    unsigned int cleared = 0, too_close = 0;
    for (const auto &x : m.samples)
      {
        bool             in;
        const auto       q        = m.query(x[0], x[1], x[2], 0, in);
        RhombicStructure expected = q;
        expected.p                = spline(m, x[0], x[1], x[2]);
        for (unsigned int i = 0; i < 4; ++i)
          expected.p[i] = std::clamp(expected.p[i], bounds[0][i], bounds[1][i]);
        cleared += expected.clear_corner(RhombicStructure::min_corner_clearance,
                                         bounds[0][3]);
        too_close +=
          q.corner_clearance() < RhombicStructure::min_corner_clearance - 1e-12;
        for (unsigned int i = 0; i < n_p; ++i)
          {
            moved    = std::max(moved, std::abs(q.p[i] - expected.p[i]));
            residual = std::max(residual, std::abs(q.p[i] - x[3 + i]));
          }
      }
    deallog << name << ": " << m.samples.size()
            << " samples; query() returns the splines there (positions "
               "clamped to the samples' range, node 4 moved off the corner at "
            << cleared << "): " << (moved == 0)
            << ", node 4's joint min_corner_clearance or more from the "
               "corner: "
            << (too_close == 0)
            << ", within 0.02 of the samples: " << (residual < 0.02)
            << std::endl;
    const char  *direction[] = {"E", "nu", "angle"};
    const double step[]      = {m.E[1] - m.E[0], m.nu[1] - m.nu[0], 2.5};
    for (unsigned int d = 0; d < 3; ++d)
      {
        const Measured s = samples_along(m, d, range);
        const Measured f = splines_along(m, d, step[d], range);
        deallog << "  along " << direction[d] << ", of the range: samples "
                << s.worst << " (" << s.n << " triples), splines " << f.worst
                << " (" << (f.n > 1000 ? "over 1000" : "FEW")
                << " points); below 1: "
                << (s.n > 0 && f.n > 0 && s.worst < 1 && f.worst < 1);
        if (d < 2)
          deallog << ", splines at most 1.5 x samples: "
                  << (f.worst <= 1.5 * s.worst);
        deallog << std::endl;
      }
  }
} // namespace

int
main()
{
  initlog();
  deallog << std::setprecision(2);
  check("map.json");
  check("map_full.json");
  check("map_tileable.json");

  // The tileable map: its samples and splines keep the joint radius p5 at
  // one value.
  {
    const MaterialMap m = MaterialMap::read(
      std::string(FORMA_SOURCE_DIR) + "/contrib/rhombic/map_tileable.json");
    AssertThrow(!m.samples.empty(), ExcMessage("no samples"));
    const double p5             = m.samples.front()[7];
    double       spread_samples = 0, spread_splines = 0;
    for (const auto &s : m.samples)
      spread_samples = std::max(spread_samples, std::abs(s[7] - p5));
    const auto   angles = m.covered_angles();
    unsigned int n      = 0;
    const int    n_a    = std::lround((angles[1] - angles[0]) / 1.25);
    for (int ia = 0; ia <= n_a; ++ia)
      for (int iE = 0; iE <= 16; ++iE)
        for (int inu = 0; inu <= 16; ++inu)
          if (const double a = angles[0] + ia * 1.25,
              E  = m.E.front() + iE * (m.E.back() - m.E.front()) / 16,
              nu = m.nu.front() + inu * (m.nu.back() - m.nu.front()) / 16;
              inside(m, E, nu, a))
            {
              spread_splines =
                std::max(spread_splines, std::abs(spline(m, E, nu, a)[4] - p5));
              ++n;
            }
    deallog << "map_tileable.json: covered angles "
            << std::to_string(angles[0]).substr(0, 5) << "-"
            << std::to_string(angles[1]).substr(0, 5) << "; p5 = " << p5
            << " at every sample: " << (spread_samples == 0) << ", at "
            << (n > 1000 ? "over 1000" : "FEW")
            << " points inside D(alpha) to 1e-7: " << (spread_splines < 1e-7)
            << std::endl;
  }

  // The check sees a branch jump: one sample of the full-size map moved
  // onto the branch the rebuild below 60 degrees met (p2 = 0.49, p4 = 0.13;
  // tests/rhombic/coverage drops such samples before a fit).
  {
    MaterialMap m    = MaterialMap::read(std::string(FORMA_SOURCE_DIR) +
                                      "/contrib/rhombic/map_full.json");
    auto       &s    = m.samples[m.samples.size() / 2];
    s[4]             = 0.49;
    s[6]             = 0.13;
    const Measured r = samples_along(m, 0, sample_ranges(m));
    deallog << "map_full.json, one sample on another branch: samples along "
               "E below 1: "
            << (r.worst < 1) << std::endl;
  }
}
