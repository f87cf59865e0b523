#include <deal.II/base/exceptions.h>
#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/vector.h>

#include <forma/base/plot.h>
#include <forma/rhombic/material_map.h>

// Boost 1.74's pchip calls isnan unqualified on double.
#include <cmath>
using std::isnan;
#include <boost/math/interpolators/pchip.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <numeric>
#include <sstream>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    TensorSpline::TensorSpline(const std::vector<double>       &lower,
                               const std::vector<double>       &upper,
                               const std::vector<unsigned int> &n,
                               const std::vector<bool>         &logarithmic)
      : lower(lower)
      , upper(upper)
      , n(n)
      , logarithmic(logarithmic.empty() ? std::vector<bool>(n.size(), false) :
                                          logarithmic)
    {
      AssertThrow(lower.size() == upper.size() && lower.size() == n.size() &&
                    !n.empty() && this->logarithmic.size() == n.size(),
                  ExcMessage("spline: inconsistent dimensions"));
      std::size_t size = 1;
      for (unsigned int k = 0; k < n.size(); ++k)
        {
          AssertThrow(n[k] >= 4,
                      ExcMessage("spline: at least 4 control points per "
                                 "direction"));
          AssertThrow(!this->logarithmic[k] || lower[k] > 0,
                      ExcMessage("spline: a logarithmic direction needs "
                                 "positive bounds, not " +
                                 std::to_string(lower[k])));
          // A degenerate direction (one value) gets a unit interval.
          if (!(this->upper[k] > this->lower[k]))
            this->upper[k] = this->lower[k] + 1;
          size *= n[k];
        }
      coefficients.assign(size, 0.);
    }



    std::pair<int, std::array<double, 4>>
    TensorSpline::basis(const unsigned int k, const double x) const
    {
      // Outside the box (and x <= 0 on a log axis) the end values hold.
      const auto coordinate = [&](const double y) {
        return !logarithmic[k] ? y : std::log(std::max(y, lower[k]));
      };
      const double a = coordinate(lower[k]);
      const double h = (coordinate(upper[k]) - a) / (n[k] - 3);
      const double t = std::clamp((coordinate(x) - a) / h, 0., n[k] - 3.);
      const int i = std::min(static_cast<int>(t), static_cast<int>(n[k]) - 4);
      const double u = t - i, v = 1 - u;
      return {i,
              {{v * v * v / 6,
                (3 * u * u * u - 6 * u * u + 4) / 6,
                (-3 * u * u * u + 3 * u * u + 3 * u + 1) / 6,
                u * u * u / 6}}};
    }



    double
    TensorSpline::value(const std::vector<double> &x) const
    {
      const unsigned int                                 d = n.size();
      std::vector<std::pair<int, std::array<double, 4>>> b;
      for (unsigned int k = 0; k < d; ++k)
        b.push_back(basis(k, x[k]));
      double             result = 0;
      std::vector<int>   m(d, 0);
      const unsigned int terms = 1u << (2 * d); // 4^d
      for (unsigned int t = 0; t < terms; ++t)
        {
          std::size_t index = 0;
          double      w     = 1;
          for (unsigned int k = 0, r = t; k < d; ++k, r /= 4)
            {
              const unsigned int a = r % 4;
              index                = index * n[k] + b[k].first + a;
              w *= b[k].second[a];
            }
          result += w * coefficients[index];
        }
      return result;
    }



    void
    TensorSpline::fit(const std::vector<std::vector<double>> &x,
                      const std::vector<double>              &y,
                      const double                            smoothing)
    {
      const unsigned int       d = n.size();
      const unsigned int       N = coefficients.size();
      LAPACKFullMatrix<double> A(N, N);
      Vector<double>           rhs(N);
      const unsigned int       terms = 1u << (2 * d);
      std::vector<std::size_t> index(terms);
      std::vector<double>      w(terms);
      for (unsigned int s = 0; s < x.size(); ++s)
        {
          std::vector<std::pair<int, std::array<double, 4>>> b;
          for (unsigned int k = 0; k < d; ++k)
            b.push_back(basis(k, x[s][k]));
          for (unsigned int t = 0; t < terms; ++t)
            {
              index[t] = 0, w[t] = 1;
              for (unsigned int k = 0, r = t; k < d; ++k, r /= 4)
                {
                  index[t] = index[t] * n[k] + b[k].first + r % 4;
                  w[t] *= b[k].second[r % 4];
                }
            }
          for (unsigned int a = 0; a < terms; ++a)
            {
              rhs(index[a]) += w[a] * y[s];
              for (unsigned int c = 0; c < terms; ++c)
                A(index[a], index[c]) += w[a] * w[c];
            }
        }
      // Second differences of the control net along every direction.
      std::vector<std::size_t> stride(d, 1);
      for (int k = d - 2; k >= 0; --k)
        stride[k] = stride[k + 1] * n[k + 1];
      for (unsigned int k = 0; k < d; ++k)
        for (std::size_t i = 0; i < N; ++i)
          {
            const unsigned int position = (i / stride[k]) % n[k];
            if (position == 0 || position + 1 == n[k])
              continue;
            const std::size_t q[3] = {i - stride[k], i, i + stride[k]};
            const double      c[3] = {1, -2, 1};
            for (unsigned int a = 0; a < 3; ++a)
              for (unsigned int b = 0; b < 3; ++b)
                A(q[a], q[b]) += smoothing * c[a] * c[b];
          }
      for (unsigned int i = 0; i < N; ++i)
        A(i, i) += 1e-12 * (1 + A(i, i));
      A.compute_cholesky_factorization();
      A.solve(rhs);
      std::copy(rhs.begin(), rhs.end(), coefficients.begin());
    }



    nlohmann::json
    TensorSpline::to_json() const
    {
      // "logarithmic" only where used, so maps without it read and write
      // as before.
      nlohmann::json j = {{"lower", lower},
                          {"upper", upper},
                          {"control_points", n},
                          {"coefficients", coefficients}};
      if (std::find(logarithmic.begin(), logarithmic.end(), true) !=
          logarithmic.end())
        j["logarithmic"] = logarithmic;
      return j;
    }



    TensorSpline
    TensorSpline::from_json(const nlohmann::json &j)
    {
      TensorSpline s(j.at("lower").get<std::vector<double>>(),
                     j.at("upper").get<std::vector<double>>(),
                     j.at("control_points").get<std::vector<unsigned int>>(),
                     j.value("logarithmic", std::vector<bool>()));
      const auto   c = j.at("coefficients").get<std::vector<double>>();
      AssertThrow(c.size() == s.coefficients.size(),
                  ExcMessage("spline: " + std::to_string(c.size()) +
                             " coefficients for " +
                             std::to_string(s.coefficients.size()) +
                             " control points"));
      s.coefficients = c;
      return s;
    }



    namespace
    {
      /// The monotone piecewise cubic (PCHIP) through (x, y), x increasing,
      /// at t (clamped to x's range); linear below 4 points.
      double
      monotone_spline(const std::vector<double> &x,
                      const std::vector<double> &y,
                      const double               t)
      {
        const double s = std::clamp(t, x.front(), x.back());
        if (x.size() == 1)
          return y[0];
        if (x.size() < 4)
          {
            const auto k =
              std::min<std::size_t>(std::upper_bound(x.begin(), x.end(), s) -
                                      x.begin(),
                                    x.size() - 1);
            const double w = (s - x[k - 1]) / (x[k] - x[k - 1]);
            return (1 - w) * y[k - 1] + w * y[k];
          }
        return boost::math::interpolators::pchip<std::vector<double>>(
          std::vector<double>(x), std::vector<double>(y))(s);
      }
    } // namespace



    unsigned int
    MaterialMap::drop_branch_jumps(const double tolerance)
    {
      const auto index = [](const std::vector<double> &grid, const double v) {
        return static_cast<int>(
          std::min_element(grid.begin(),
                           grid.end(),
                           [v](const double a, const double b) {
                             return std::abs(a - v) < std::abs(b - v);
                           }) -
          grid.begin());
      };
      // Sample index per (angle, E, nu) node; -1 where there is none.
      std::vector<int> at(angles.size() * E.size() * nu.size(), -1);
      const auto       node = [&](const int a, const int i, const int j) {
        return (a * static_cast<int>(E.size()) + i) *
                 static_cast<int>(nu.size()) +
               j;
      };
      std::vector<std::array<int, 3>> where(samples.size());
      for (unsigned int k = 0; k < samples.size(); ++k)
        {
          where[k] = {{index(angles, samples[k][2]),
                       index(E, samples[k][0]),
                       index(nu, samples[k][1])}};
          at[node(where[k][0], where[k][1], where[k][2])] = k;
        }
      // Angles in order, so "neighbouring angles" are adjacent in value.
      std::vector<int> order(angles.size()), rank(angles.size());
      std::iota(order.begin(), order.end(), 0);
      std::sort(order.begin(), order.end(), [&](int a, int b) {
        return angles[a] < angles[b];
      });
      for (unsigned int r = 0; r < order.size(); ++r)
        rank[order[r]] = r;

      std::vector<bool> drop(samples.size(), false);
      for (unsigned int k = 0; k < samples.size(); ++k)
        {
          const auto [a, i, j] = where[k];
          std::vector<int> neighbours;
          for (int di = -1; di <= 1; ++di)
            for (int dj = -1; dj <= 1; ++dj)
              if ((di != 0 || dj != 0) && i + di >= 0 &&
                  i + di < static_cast<int>(E.size()) && j + dj >= 0 &&
                  j + dj < static_cast<int>(nu.size()))
                neighbours.push_back(at[node(a, i + di, j + dj)]);
          for (const int dr : {-1, 1})
            if (rank[a] + dr >= 0 &&
                rank[a] + dr < static_cast<int>(angles.size()))
              neighbours.push_back(at[node(order[rank[a] + dr], i, j)]);
          neighbours.erase(std::remove(neighbours.begin(),
                                       neighbours.end(),
                                       -1),
                           neighbours.end());
          if (neighbours.size() < 3)
            continue;
          for (unsigned int p = 3; p < samples[k].size() && !drop[k]; ++p)
            {
              std::vector<double> v;
              for (const int n : neighbours)
                v.push_back(samples[n][p]);
              std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
              drop[k] = std::abs(samples[k][p] - v[v.size() / 2]) > tolerance;
            }
        }
      std::vector<std::array<double, 11>> kept;
      for (unsigned int k = 0; k < samples.size(); ++k)
        if (drop[k])
          {
            const auto [a, i, j]          = where[k];
            covered[a][i * nu.size() + j] = false;
          }
        else
          kept.push_back(samples[k]);
      const unsigned int n = samples.size() - kept.size();
      samples              = std::move(kept);
      return n;
    }



    double
    MaterialMap::coverage_coordinate(const double E_relative) const
    {
      return log_coverage ? std::log(E_relative) : E_relative;
    }



    void
    MaterialMap::fit_coverage_polygons(const double height_weight)
    {
      std::vector<double> x;
      for (const double e : E)
        x.push_back(coverage_coordinate(e));
      polygons.assign(coverage_pieces, {});
      for (const auto &c : covered)
        {
          const auto p =
            fit_coverage_pieces(x, nu, c, height_weight, coverage_pieces);
          for (unsigned int k = 0; k < coverage_pieces; ++k)
            polygons[k].push_back(p[k]);
        }
      fit_polygon_splines();
    }



    void
    MaterialMap::fit_polygon_splines()
    {
      // Angles from the largest down while some piece has a polygon: one
      // range for all pieces, so that D(alpha) is never empty inside it. A
      // piece without a polygon at one of these angles takes another
      // piece's (the union is the same), so that its splines run through.
      std::vector<unsigned int> order(angles.size());
      std::iota(order.begin(), order.end(), 0u);
      std::sort(order.begin(),
                order.end(),
                [&](unsigned int i, unsigned int k) {
                  return angles[i] > angles[k];
                });
      const auto first_nonempty = [&](const unsigned int a) {
        for (unsigned int k = 0; k < polygons.size(); ++k)
          if (polygons[k][a].E_min < polygons[k][a].E_max)
            return static_cast<int>(k);
        return -1;
      };
      std::vector<unsigned int> used;
      for (const auto a : order)
        if (first_nonempty(a) >= 0)
          used.push_back(a);
        else if (!used.empty())
          break;
      polygon_splines.assign(polygons.size(), {});
      if (used.empty())
        return;
      for (unsigned int k = 0; k < polygons.size(); ++k)
        {
          PolygonSplines &s = polygon_splines[k];
          s.range           = {{angles[used.back()], angles[used.front()]}};
          for (auto a = used.rbegin(); a != used.rend(); ++a)
            {
              const CoveragePolygon &p =
                polygons[k][*a].E_min < polygons[k][*a].E_max ?
                  polygons[k][*a] :
                  polygons[first_nonempty(*a)][*a];
              s.angles.push_back(angles[*a]);
              for (unsigned int c = 0; c < CoveragePolygon::n_coefficients; ++c)
                s.values[c].push_back(p.coefficients()[c]);
            }
        }
    }



    CoveragePolygon
    MaterialMap::coverage_polygon(const double       alpha_degrees,
                                  const unsigned int piece) const
    {
      CoveragePolygon polygon;
      polygon.E_min = 1; // empty
      if (piece >= polygon_splines.size())
        return polygon;
      const PolygonSplines &s = polygon_splines[piece];
      if (alpha_degrees < s.range[0] - 1e-9 ||
          alpha_degrees > s.range[1] + 1e-9)
        return polygon;
      std::array<double, CoveragePolygon::n_coefficients> c;
      for (unsigned int k = 0; k < c.size(); ++k)
        c[k] = monotone_spline(s.angles, s.values[k], alpha_degrees);
      return CoveragePolygon::from_coefficients(c,
                                                coverage_coordinate(E.front()),
                                                coverage_coordinate(E.back()));
    }



    CoverageRegion
    MaterialMap::coverage(const double alpha_degrees,
                          const double base_nu) const
    {
      // In (x, nu_map) with nu_map = nu - base_nu E (eq. 4.11 backwards).
      // A piece whose interpolated lines shut it out entirely (its
      // outline empty) is left out rather than made an infeasible region.
      std::vector<HalfPlaneRegion> pieces;
      for (unsigned int k = 0; k < polygon_splines.size(); ++k)
        {
          const CoveragePolygon polygon = coverage_polygon(alpha_degrees, k);
          if (polygon.outline().empty())
            continue;
          HalfPlaneRegion planes;
          for (const auto &h : polygon.half_planes())
            planes.push_back({h[0], h[1], h[2]});
          pieces.push_back(planes);
        }
      return CoverageRegion(pieces, log_coverage, base_nu);
    }



    std::array<double, 2>
    MaterialMap::covered_angles() const
    {
      // Where D(alpha) exists; a map without polygons falls back to the
      // angles with covered nodes.
      std::array<double, 2> range = {{1e300, -1e300}};
      for (const auto &s : polygon_splines)
        if (s.range[0] <= s.range[1])
          range = {
            {std::min(range[0], s.range[0]), std::max(range[1], s.range[1])}};
      if (range[0] <= range[1])
        return range;
      for (unsigned int a = 0; a < angles.size(); ++a)
        if (std::count(covered[a].begin(), covered[a].end(), true) >= 3)
          {
            range[0] = std::min(range[0], angles[a]);
            range[1] = std::max(range[1], angles[a]);
          }
      AssertThrow(range[0] <= range[1],
                  ExcMessage("the material map covers no angle"));
      return range;
    }



    RhombicStructure
    MaterialMap::query(const double E,
                       const double nu,
                       const double alpha_degrees,
                       const double base_nu,
                       bool        &inside) const
    {
      AssertThrow(!angles.empty(), ExcMessage("the material map is empty"));
      // The map is for a base with nu = 0: eq. 4.11 backwards.
      const double nu_map = nu - base_nu * E;
      inside              = false;
      inside = coverage(alpha_degrees, base_nu).contains({{E, nu}});
      RhombicStructure s;
      s.alpha    = alpha_degrees * M_PI / 180;
      s.blending = blending;
      // Node positions (p1..p4) are clamped to the samples' range (one range
      // over all angles): near the coverage's edges the splines overshoot
      // it, and a node moved further than any sample can reach a neighbour
      // and change the topology (at 47 degrees node 4's joint reaches the
      // cell's obtuse corner for p4 > 0.9 and joins its image there: E
      // doubles). Radii are clamped only a little inside the geometry's
      // limits: beyond the samples a strut thins or thickens continuously,
      // and where the construction's bounds stopped the samples (p8 >=
      // 0.015 below 60 degrees) the splines' thinner struts are the accurate
      // ones (doc/rhombic.md). The upper bounds without samples keep nodes
      // and joints off the cell's corners (the geometry allows 0.99, 0.6).
      constexpr double max_position = 0.95, max_radius = 0.55;
      auto             range = RhombicStructure::limits();
      for (unsigned int i = 0; i < RhombicStructure::n_parameters; ++i)
        range[i][1] = i < 4 ? max_position : max_radius;
      if (!samples.empty())
        {
          for (unsigned int i = 0; i < 4; ++i)
            range[i] = {{samples[0][3 + i], samples[0][3 + i]}};
          for (const auto &x : samples)
            for (unsigned int i = 0; i < 4; ++i)
              {
                range[i][0] = std::min(range[i][0], x[3 + i]);
                range[i][1] = std::max(range[i][1], x[3 + i]);
              }
        }
      for (unsigned int i = 0; i < RhombicStructure::n_parameters; ++i)
        s.p[i] = std::clamp(parameters[i].value({E, nu_map, alpha_degrees}),
                            range[i][0],
                            range[i][1]);
      // Node 2 stays inside its triangle (check()): p1 and p2 are clamped
      // separately, and their largest values need not come from one sample.
      s.p[1] = std::max(range[1][0], std::min(s.p[1], 0.99 - s.p[0]));
      // The range does not keep node 4's joint off the corner, which
      // depends on the angle and the radii: at (0.025, 0.025, 55 degrees)
      // the full map's p4 = 0.9 joins it to its image there (E/E_b 0.118
      // for 0.025), and some of its samples are within 1e-6 of that edge.
      s.clear_corner(RhombicStructure::min_corner_clearance, range[3][0]);
      return s;
    }



    void
    MaterialMap::write(const std::string &file_name) const
    {
      nlohmann::json j;
      // Format 2: splines uniform in log E, which a reader of format 1
      // would evaluate on a linear axis without noticing; format 3:
      // coverage polygons in log E or in pieces, which a reader of format 2
      // would read as linear or lose.
      const bool format_3 = log_coverage || polygons.size() > 1;
      j["format"]         = format_3 ? "forma-rhombic material map 3" :
                            parameters[0].is_logarithmic(0) ?
                                       "forma-rhombic material map 2" :
                                       "forma-rhombic material map 1";
      j["base"]           = {{"E", 1}, {"nu", 0}};
      j["axes"]           = {"E/E_b", "nu", "angle_degrees"};
      j["blending"]       = blending;
      j["grid"]           = {{"E", E}, {"nu", nu}, {"angles", angles}};
      j["covered"]        = covered;
      if (!build_settings.empty())
        j["build_settings"] = build_settings;
      // A build's progress file has no splines yet.
      if (parameters[0].n_coefficients() > 0)
        for (const auto &p : parameters)
          j["parameters"].push_back(p.to_json());
      j["samples"]            = samples;
      const auto coefficients = [](const std::vector<CoveragePolygon> &p) {
        nlohmann::json c = nlohmann::json::array();
        for (const auto &q : p)
          c.push_back(q.coefficients());
        return c;
      };
      if (format_3)
        {
          j["coverage_axis"]   = log_coverage ? "log E/E_b" : "E/E_b";
          j["coverage_pieces"] = nlohmann::json::array();
          for (const auto &p : polygons)
            j["coverage_pieces"].push_back(coefficients(p));
        }
      else if (!polygons.empty())
        j["coverage_polygons"] = coefficients(polygons[0]);
      std::ofstream out(file_name);
      AssertThrow(out, ExcMessage("cannot write the map '" + file_name + "'"));
      out << j.dump() << '\n';
    }



    MaterialMap
    MaterialMap::read(const std::string &file_name, const bool with_splines)
    {
      std::ifstream in(file_name);
      AssertThrow(in,
                  ExcMessage("cannot read the material map '" + file_name +
                             "'"));
      return read(in, file_name, with_splines);
    }



    MaterialMap
    MaterialMap::read(std::istream      &in,
                      const std::string &file_name,
                      const bool         with_splines)
    {
      MaterialMap map;
      try
        {
          const auto j      = nlohmann::json::parse(in);
          const auto format = j.at("format");
          AssertThrow(format == "forma-rhombic material map 1" ||
                        format == "forma-rhombic material map 2" ||
                        format == "forma-rhombic material map 3",
                      ExcMessage("not a forma-rhombic material map (format "
                                 "1, 2 or 3)"));
          const bool format_3 = format == "forma-rhombic material map 3";
          if (format_3)
            {
              const auto axis = j.at("coverage_axis").get<std::string>();
              AssertThrow(axis == "E/E_b" || axis == "log E/E_b",
                          ExcMessage("coverage_axis is '" + axis +
                                     "', not 'E/E_b' or 'log E/E_b'"));
              AssertThrow(!j.at("coverage_pieces").empty(),
                          ExcMessage("coverage_pieces is empty"));
              map.log_coverage = axis == "log E/E_b";
            }
          map.blending = j.at("blending").get<double>();
          map.E        = j.at("grid").at("E").get<std::vector<double>>();
          map.nu       = j.at("grid").at("nu").get<std::vector<double>>();
          map.angles   = j.at("grid").at("angles").get<std::vector<double>>();
          map.covered  = j.at("covered").get<std::vector<std::vector<bool>>>();
          if (j.contains("build_settings"))
            map.build_settings = j.at("build_settings");
          if (j.contains("samples"))
            map.samples =
              j.at("samples").get<std::vector<std::array<double, 11>>>();
          AssertThrow(map.covered.size() == map.angles.size(),
                      ExcMessage("the map's coverage does not match its "
                                 "angles"));
          for (const auto &c : map.covered)
            AssertThrow(c.size() == map.E.size() * map.nu.size(),
                        ExcMessage("the map's coverage does not match its "
                                   "(E, nu) grid"));
          AssertThrow(map.E.size() >= 2 && map.nu.size() >= 2,
                      ExcMessage("the map's (E, nu) grid needs 2 x 2 nodes"));
          AssertThrow(!map.log_coverage ||
                        *std::min_element(map.E.begin(), map.E.end()) > 0,
                      ExcMessage("the map's coverage axis is log E/E_b, but "
                                 "its grid's moduli are not all positive"));
          if (!with_splines)
            return map;
          const auto &p = j.at("parameters");
          AssertThrow(p.size() == RhombicStructure::n_parameters,
                      ExcMessage("the map needs 8 parameter splines"));
          for (const auto &spline : p)
            AssertThrow(spline.at("control_points").size() == 3,
                        ExcMessage("the map's splines must be functions of "
                                   "(E, nu, alpha)"));
          for (unsigned int i = 0; i < p.size(); ++i)
            map.parameters[i] = TensorSpline::from_json(p[i]);
          // Per piece, the coefficients at every angle.
          std::vector<nlohmann::json> pieces;
          if (format_3)
            for (const auto &p : j.at("coverage_pieces"))
              pieces.push_back(p);
          else if (j.contains("coverage_polygons"))
            pieces.push_back(j.at("coverage_polygons"));
          AssertThrow(pieces.size() <= 2,
                      ExcMessage("the map's coverage has 1 or 2 pieces, not " +
                                 std::to_string(pieces.size())));
          for (const auto &piece : pieces)
            {
              const auto c = piece.get<std::vector<
                std::array<double, CoveragePolygon::n_coefficients>>>();
              AssertThrow(c.size() == map.angles.size(),
                          ExcMessage("the map's coverage polygons do not "
                                     "match its angles"));
              map.polygons.emplace_back();
              for (const auto &k : c)
                map.polygons.back().push_back(
                  CoveragePolygon::from_coefficients(
                    k,
                    map.coverage_coordinate(map.E.front()),
                    map.coverage_coordinate(map.E.back())));
            }
          map.coverage_pieces = std::max<std::size_t>(pieces.size(), 1);
          if (pieces.empty()) // format 1 or 2 written before the polygons
            map.fit_coverage_polygons();
          else
            map.fit_polygon_splines();
        }
      catch (const nlohmann::json::exception &e)
        {
          AssertThrow(false,
                      ExcMessage("the material map '" + file_name +
                                 "' is malformed: " + e.what()));
        }
      return map;
    }



    void
    MaterialMap::write_parameter_surfaces(const std::string &file_name,
                                          const double       angle) const
    {
      // Parameter surfaces (Fig. 4.17): p1..p4 in the top row, p5..p8
      // below; nu along x, E up; gray outside the coverage.
      // A map whose splines are uniform in log E is drawn over log10 E.
      const bool              log_E = parameters[0].is_logarithmic(0);
      const unsigned int      P     = 120;
      std::vector<FieldPanel> panels(RhombicStructure::n_parameters);
      for (unsigned int i = 0; i < panels.size(); ++i)
        panels[i].title = "p_" + std::to_string(i + 1);
      const std::array<double, 2> y_range =
        log_E ?
          std::array<double, 2>{{std::log10(E.front()), std::log10(E.back())}} :
          std::array<double, 2>{{E.front(), E.back()}};
      for (unsigned int r = 0; r < P; ++r)
        for (unsigned int c = 0; c < P; ++c)
          {
            const double y =
              y_range[0] + (y_range[1] - y_range[0]) * (P - 1 - r) / (P - 1);
            const double E_rc = log_E ? std::pow(10., y) : y;
            const double nu_rc =
              nu.front() + (nu.back() - nu.front()) * c / (P - 1);
            bool inside;
            query(E_rc, nu_rc, angle, 0, inside);
            for (unsigned int i = 0; i < panels.size(); ++i)
              {
                panels[i].values.push_back(
                  parameters[i].value({E_rc, nu_rc, angle}));
                panels[i].defined.push_back(inside);
              }
          }
      std::ostringstream title;
      title << "Map parameters at α = " << std::setprecision(3) << angle << "°";
      write_field_panels(file_name,
                         panels,
                         P,
                         P,
                         {{nu.front(), nu.back()}},
                         y_range,
                         title.str(),
                         "Poisson's ratio ν",
                         log_E ? "log_{10}(E / E_b)" : "E / E_b");
    }



    void
    MaterialMap::write_coverage_plot(const std::string         &file_name,
                                     const std::vector<double> &only) const
    {
      const std::array<std::array<std::uint8_t, 3>, 8> colors = {
        {{{200, 30, 30}},
         {{235, 150, 40}},
         {{40, 140, 60}},
         {{31, 90, 180}},
         {{120, 60, 170}},
         {{140, 90, 40}},
         {{20, 150, 150}},
         {{220, 90, 160}}}};
      const bool              log_E = parameters[0].is_logarithmic(0);
      std::vector<PlotSeries> series;
      double                  top = 0;
      for (const double x : only)
        AssertThrow(std::any_of(angles.begin(),
                                angles.end(),
                                [&](const double a) {
                                  return std::abs(x - a) < 1e-9;
                                }),
                    ExcMessage("coverage plot: " + std::to_string(x) +
                               " degrees is not one of the map's angles"));
      unsigned int drawn = 0; // picks the color and the marker size
      for (unsigned int a = 0; a < angles.size(); ++a)
        {
          if (!only.empty() &&
              std::none_of(only.begin(), only.end(), [&](const double x) {
                return std::abs(x - angles[a]) < 1e-9;
              }))
            continue;
          PlotSeries s;
          for (unsigned int n = 0; n < E.size() * nu.size(); ++n)
            if (covered[a][n])
              {
                s.points.push_back({{nu[n % nu.size()], E[n / nu.size()]}});
                top = std::max(top, E[n / nu.size()]);
              }
          std::ostringstream label;
          label << "α = " << std::setprecision(3) << angles[a] << "°";
          s.color = colors[drawn % colors.size()];
          s.size  = 5 - std::min<int>(drawn, 3);
          ++drawn;
          s.label = label.str();
          series.push_back(s);
          for (const auto &piece : polygons) // D(alpha)'s polygons
            if (a < piece.size())
              {
                PlotSeries outline;
                // Edges subdivided where the plot's E axis is not the
                // polygon's: the slanted ones curve there.
                const auto         corners = piece[a].outline();
                const unsigned int subdivisions =
                  log_E != log_coverage ? 16 : 1;
                const auto point = [&](const std::array<double, 2> &c) {
                  return std::array<double, 2>{
                    {c[0], log_coverage ? std::exp(c[1]) : c[1]}};
                };
                for (std::size_t k = 0; k + 1 < corners.size(); ++k)
                  for (unsigned int t = 0; t < subdivisions; ++t)
                    outline.points.push_back(point(
                      {{corners[k][0] + (corners[k + 1][0] - corners[k][0]) *
                                          t / subdivisions,
                        corners[k][1] + (corners[k + 1][1] - corners[k][1]) *
                                          t / subdivisions}}));
                if (!corners.empty())
                  outline.points.push_back(point(corners.back()));
                outline.line  = true;
                outline.color = s.color;
                series.push_back(outline);
              }
        }
      write_xy_plot(file_name,
                    series,
                    "Material map coverage",
                    "Poisson's ratio ν",
                    "E / E_b",
                    {{-1, 1}},
                    log_E ?
                      std::array<double, 2>{
                        {E.front() / 1.25, 1.25 * E.back()}} :
                      std::array<double, 2>{{0, 1.1 * std::max(top, 1e-3)}},
                    {{false, log_E}});
    }
  } // namespace rhombic
} // namespace forma
