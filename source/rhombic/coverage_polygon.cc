#include <deal.II/base/exceptions.h>

#include <forma/rhombic/coverage_polygon.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    namespace
    {
      // A line nu(E) = a + b E.
      struct Line
      {
        double a, b;
        double
        operator()(const double E) const
        {
          return a + b * E;
        }
      };

      // Integral over [E_lo, E_hi] of max(floor, line) (sign = +1) or
      // min(ceiling, line) (sign = -1): exact, the line crosses the bound
      // at most once.
      double
      clipped_integral(const Line  &l,
                       const double bound,
                       const double E_lo,
                       const double E_hi,
                       const double sign)
      {
        const auto piece = [&](const double e0, const double e1) {
          const double mid = 0.5 * (e0 + e1);
          const double v   = sign * (l(mid) - bound) > 0 ? l(mid) : bound;
          return v * (e1 - e0);
        };
        if (l.b != 0)
          {
            const double cross = (bound - l.a) / l.b;
            if (cross > E_lo && cross < E_hi)
              return piece(E_lo, cross) + piece(cross, E_hi);
          }
        return piece(E_lo, E_hi);
      }

      // Per row of an (E, nu) grid, the longest run of covered nodes: [lo,
      // hi] node indices ({-1, -2}: none).
      std::vector<std::array<int, 2>>
      longest_runs(const std::vector<bool> &covered,
                   const unsigned int       nE,
                   const unsigned int       nn)
      {
        std::vector<std::array<int, 2>> run(nE, {{-1, -2}});
        for (unsigned int i = 0; i < nE; ++i)
          for (unsigned int j = 0; j < nn;)
            {
              if (!covered[i * nn + j])
                {
                  ++j;
                  continue;
                }
              unsigned int k = j;
              while (k + 1 < nn && covered[i * nn + k + 1])
                ++k;
              if (static_cast<int>(k - j) > run[i][1] - run[i][0])
                run[i] = {{static_cast<int>(j), static_cast<int>(k)}};
              j = k + 1;
            }
        return run;
      }



      // A side of a polygon over [E_a, E_b]: sign +1, the left, the line at
      // or right of `points` (nu, E) with the least integral of max(bound,
      // line); -1, the right, mirrored. The objective is convex in the line
      // and the constraints are linear: the optimum is on a line through a
      // point, at the best slope among those that keep the others (golden
      // section), slopes within +-steep. Nothing if no line keeps them.
      std::optional<Line>
      best_side_line(const std::vector<std::array<double, 2>> &points,
                     const double                              bound,
                     const double                              sign,
                     const double                              E_a,
                     const double                              E_b,
                     const double                              steep)
      {
        if (points.empty())
          return Line{bound, 0};
        const auto value_of_line = [&](const Line &l) {
          return sign * clipped_integral(l, bound, E_a, E_b, sign);
        };
        std::optional<Line> chosen;
        double              value = std::numeric_limits<double>::infinity();
        for (const auto &P : points)
          {
            double b_lo = -steep, b_hi = steep;
            for (const auto &Q : points)
              {
                const double dE = Q[1] - P[1];
                if (dE == 0)
                  continue;
                // sign (nu_P + s dE - nu_Q) >= 0
                const double s = (Q[0] - P[0]) / dE;
                if (sign * dE > 0)
                  b_lo = std::max(b_lo, s);
                else
                  b_hi = std::min(b_hi, s);
              }
            if (b_lo > b_hi + 1e-12)
              continue;
            const auto line = [&](const double slope) {
              return Line{P[0] - slope * P[1], slope};
            };
            double       lo = b_lo, hi = b_hi;
            const double g = 0.5 * (std::sqrt(5.) - 1);
            for (unsigned int k = 0; k < 200 && hi - lo > 1e-12; ++k)
              {
                const double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
                if (value_of_line(line(m1)) <= value_of_line(line(m2)))
                  hi = m2;
                else
                  lo = m1;
              }
            for (const double slope : {b_lo, b_hi, 0.5 * (lo + hi)})
              {
                const double v = value_of_line(line(slope));
                if (v < value - 1e-14)
                  value = v, chosen = line(slope);
              }
          }
        return chosen;
      }
    } // namespace



    double
    CoveragePolygon::left_nu(const double E) const
    {
      return left[0] + (left[1] - left[0]) * (E - E_0) / (E_1 - E_0);
    }

    double
    CoveragePolygon::right_nu(const double E) const
    {
      return right[0] + (right[1] - right[0]) * (E - E_0) / (E_1 - E_0);
    }

    std::vector<std::array<double, 3>>
    CoveragePolygon::half_planes() const
    {
      if (!(E_min < E_max && nu_min < nu_max))
        return {};
      std::vector<std::array<double, 3>> h = {{{-1, 0, -E_min}},
                                              {{1, 0, E_max}},
                                              {{0, -1, -nu_min}},
                                              {{0, 1, nu_max}}};
      // nu >= s_l(E):  (dnu/dE) E - nu <= -s_l(0); nu <= s_r(E) likewise.
      const double bl = (left[1] - left[0]) / (E_1 - E_0),
                   br = (right[1] - right[0]) / (E_1 - E_0);
      const double nl = std::hypot(bl, 1.), nr = std::hypot(br, 1.);
      h.push_back({{bl / nl, -1 / nl, -left_nu(0) / nl}});
      h.push_back({{-br / nr, 1 / nr, right_nu(0) / nr}});
      return h;
    }

    std::vector<std::array<double, 2>>
    CoveragePolygon::outline() const
    {
      if (!(E_min < E_max && nu_min < nu_max))
        return {};
      // The box clipped by the slanted half-planes (Sutherland-Hodgman).
      std::vector<std::array<double, 2>> poly = {{{nu_min, E_min}},
                                                 {{nu_max, E_min}},
                                                 {{nu_max, E_max}},
                                                 {{nu_min, E_max}}};
      for (const auto &h : half_planes())
        {
          const auto g = [&](const std::array<double, 2> &x) {
            return h[0] * x[1] + h[1] * x[0] - h[2]; // <= 0 inside
          };
          std::vector<std::array<double, 2>> clipped;
          for (unsigned int k = 0; k < poly.size(); ++k)
            {
              const auto  &p = poly[k], &q = poly[(k + 1) % poly.size()];
              const double gp = g(p), gq = g(q);
              if (gp <= 0)
                clipped.push_back(p);
              if ((gp < 0 && gq > 0) || (gp > 0 && gq < 0))
                {
                  const double t = gp / (gp - gq);
                  clipped.push_back(
                    {{p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])}});
                }
            }
          poly = clipped;
          if (poly.empty())
            return {};
        }
      poly.push_back(poly.front());
      return poly;
    }

    double
    CoveragePolygon::area(const double nu_extent) const
    {
      if (!(E_min < E_max && nu_min < nu_max))
        return 0;
      // The width is concave in E: exact with the kinks as sample points.
      std::vector<double> E = {E_min, E_max};
      for (const auto &[line_at, bound] :
           {std::make_pair(&CoveragePolygon::left_nu, nu_min),
            std::make_pair(&CoveragePolygon::right_nu, nu_max)})
        {
          const double v0 = (this->*line_at)(E_0), v1 = (this->*line_at)(E_1);
          if (v1 != v0)
            {
              const double e = E_0 + (bound - v0) / (v1 - v0) * (E_1 - E_0);
              if (e > E_min && e < E_max)
                E.push_back(e);
            }
        }
      // Where the slanted lines cross each other.
      {
        const double d0 = right_nu(E_0) - left_nu(E_0),
                     d1 = right_nu(E_1) - left_nu(E_1);
        if (d1 != d0)
          {
            const double e = E_0 + d0 / (d0 - d1) * (E_1 - E_0);
            if (e > E_min && e < E_max)
              E.push_back(e);
          }
      }
      std::sort(E.begin(), E.end());
      const auto width = [&](const double e) {
        return std::max(0.,
                        std::min(nu_max, right_nu(e)) -
                          std::max(nu_min, left_nu(e)));
      };
      double a = 0;
      for (unsigned int k = 0; k + 1 < E.size(); ++k)
        a += 0.5 * (width(E[k]) + width(E[k + 1])) * (E[k + 1] - E[k]);
      return a / ((E_1 - E_0) * nu_extent);
    }

    std::array<double, CoveragePolygon::n_coefficients>
    CoveragePolygon::coefficients() const
    {
      return {
        {E_min, E_max, nu_min, nu_max, left[0], left[1], right[0], right[1]}};
    }

    CoveragePolygon
    CoveragePolygon::from_coefficients(
      const std::array<double, n_coefficients> &c,
      const double                              E_0,
      const double                              E_1)
    {
      CoveragePolygon p;
      p.E_min  = c[0];
      p.E_max  = c[1];
      p.nu_min = c[2];
      p.nu_max = c[3];
      p.left   = {{c[4], c[5]}};
      p.right  = {{c[6], c[7]}};
      p.E_0    = E_0;
      p.E_1    = E_1;
      return p;
    }



    CoveragePolygon
    fit_coverage_polygon(const std::vector<double> &E,
                         const std::vector<double> &nu,
                         const std::vector<bool>   &covered,
                         const double               height_weight)
    {
      const unsigned int nE = E.size(), nn = nu.size();
      AssertThrow(nE >= 2 && nn >= 2 && covered.size() == nE * nn,
                  ExcMessage("coverage polygon: the coverage does not match "
                             "an (E, nu) grid of at least 2 x 2 nodes"));
      AssertThrow(std::is_sorted(E.begin(), E.end(), std::less_equal<>()) &&
                    std::is_sorted(nu.begin(), nu.end(), std::less_equal<>()),
                  ExcMessage("coverage polygon: the grid's E and nu values "
                             "must increase"));
      CoveragePolygon best;
      best.E_0   = E.front();
      best.E_1   = E.back();
      best.E_min = 1, best.E_max = 0; // empty
      const double nu_extent = nu.back() - nu.front();

      const auto run = longest_runs(covered, nE, nn);
      // Lines at most twice as steep as the grid's diagonal: a steeper one
      // would cut a corner as E_min or E_max does, with coefficients that
      // do not spline.
      const double steep = 2 * nu_extent / (E.back() - E.front());

      double best_value = -std::numeric_limits<double>::infinity();
      for (unsigned int a = 0; a < nE; ++a)
        for (unsigned int b = a + 1; b < nE; ++b)
          {
            // Every row in [a, b] covered.
            if (std::any_of(run.begin() + a,
                            run.begin() + b + 1,
                            [](const auto &r) { return r[0] < 0; }))
              continue;
            // nu_min and nu_max: grid values within the rows' overall span
            // (the slanted lines keep the rows' own bounds).
            int span_lo = nn, span_hi = -1;
            for (unsigned int i = a; i <= b; ++i)
              {
                span_lo = std::min(span_lo, run[i][0]);
                span_hi = std::max(span_hi, run[i][1]);
              }
            for (int jl = span_lo; jl <= span_hi; ++jl)
              for (int jr = jl + 1; jr <= span_hi; ++jr)
                {
                  const double nmin = nu[jl], nmax = nu[jr];
                  // Left: max(nmin, s_l(E_i)) >= nu of the row's first
                  // node; candidates through two of these points or the
                  // corners (nmin, E_a), (nmin, E_b).
                  std::vector<std::array<double, 2>> pl, pr;
                  for (unsigned int i = a; i <= b; ++i)
                    {
                      if (nu[run[i][0]] > nmin)
                        pl.push_back({{nu[run[i][0]], E[i]}});
                      if (nu[run[i][1]] < nmax)
                        pr.push_back({{nu[run[i][1]], E[i]}});
                    }
                  // A row must reach between the box's sides.
                  bool row_ok = true;
                  for (unsigned int i = a; i <= b; ++i)
                    row_ok =
                      row_ok && nu[run[i][0]] < nmax && nu[run[i][1]] > nmin;
                  if (!row_ok)
                    continue;
                  const auto left =
                               best_side_line(pl, nmin, 1, E[a], E[b], steep),
                             right =
                               best_side_line(pr, nmax, -1, E[a], E[b], steep);
                  if (!left || !right)
                    continue; // no line keeps the points
                  const Line     &l = *left, &r = *right;
                  CoveragePolygon c;
                  c.E_0              = E.front();
                  c.E_1              = E.back();
                  c.E_min            = E[a];
                  c.E_max            = E[b];
                  c.nu_min           = nmin;
                  c.nu_max           = nmax;
                  c.left             = {{l(c.E_0), l(c.E_1)}};
                  c.right            = {{r(c.E_0), r(c.E_1)}};
                  const double value = c.area(nu_extent) + height_weight *
                                                             (c.E_max - c.E_0) /
                                                             (c.E_1 - c.E_0);
                  if (value > best_value + 1e-12)
                    best_value = value, best = c;
                }
          }
      return best;
    }



    std::vector<CoveragePolygon>
    fit_coverage_pieces(const std::vector<double> &E,
                        const std::vector<double> &nu,
                        const std::vector<bool>   &covered,
                        const double               height_weight,
                        const unsigned int         pieces)
    {
      AssertThrow(pieces == 1 || pieces == 2,
                  ExcMessage("coverage polygon: 1 or 2 pieces, not " +
                             std::to_string(pieces)));
      if (pieces == 1 || E.size() < 3)
        return std::vector<CoveragePolygon>(
          pieces, fit_coverage_polygon(E, nu, covered, height_weight));
      const unsigned int nn = nu.size();
      const auto band = [&](const unsigned int lo, const unsigned int hi) {
        std::vector<bool> c(covered.size(), false);
        for (unsigned int i = lo; i <= hi; ++i)
          for (unsigned int j = 0; j < nn; ++j)
            c[i * nn + j] = covered[i * nn + j];
        return c;
      };
      const auto value = [&](const std::vector<CoveragePolygon> &p) {
        double v = 0, top = -std::numeric_limits<double>::infinity();
        for (const auto &q : p)
          if (q.E_min < q.E_max)
            {
              v += q.area(nu.back() - nu.front());
              top = std::max(top, q.E_max);
            }
        return top > -std::numeric_limits<double>::infinity() ?
                 v +
                   height_weight * (top - E.front()) / (E.back() - E.front()) :
                 v;
      };
      std::vector<CoveragePolygon> best;
      double best_value = -std::numeric_limits<double>::infinity();
      for (unsigned int s = 1; s + 1 < E.size(); ++s)
        {
          const std::vector<CoveragePolygon> p = {
            fit_coverage_polygon(E, nu, band(0, s), 0),
            fit_coverage_polygon(E, nu, band(s, E.size() - 1), height_weight)};
          if (value(p) > best_value + 1e-12)
            best_value = value(p), best = p;
        }
      return best;
    }
  } // namespace rhombic
} // namespace forma
