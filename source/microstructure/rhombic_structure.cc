#include <deal.II/base/exceptions.h>

#include <forma/microstructure/rhombic_structure.h>

#include "ad_value.h"
#include <boost/math/tools/toms748_solve.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

namespace forma
{
  using namespace dealii;

  namespace
  {
    using internal::value_of;
    /// Short for value_of() in the many branch decisions below.
    template <typename T>
    double
    val(const T &x)
    {
      return value_of(x);
    }

    // The rhombus's symmetries on the reference square, centered: identity,
    // the two diagonal reflections and their product (the point inversion).
    template <typename Number>
    std::array<Number, 2>
    symmetry(const unsigned int g, const std::array<Number, 2> &u)
    {
      switch (g)
        {
          case 0:
            return u;
          case 1:
            return {{u[1], u[0]}};
          case 2:
            return {{-u[1], -u[0]}};
          default:
            return {{-u[0], -u[1]}};
        }
    }
  } // namespace



  std::array<std::array<double, 2>, RhombicStructure::n_parameters>
  RhombicStructure::ranges()
  {
    return {{{{0.1, 0.5}},
             {{0.1, 0.5}},
             {{0.1, 0.9}},
             {{0.1, 0.9}},
             {{0.05, 0.3}},
             {{0.05, 0.3}},
             {{0.05, 0.3}},
             {{0.05, 0.3}}}};
  }



  std::array<std::array<double, 2>, RhombicStructure::n_parameters>
  RhombicStructure::limits()
  {
    std::array<std::array<double, 2>, n_parameters> r;
    for (unsigned int i = 0; i < n_parameters; ++i)
      r[i] = {{0.01, i < 4 ? 0.99 : 0.6}};
    return r;
  }



  std::string
  RhombicStructure::parameter_name(const unsigned int i)
  {
    return "p" + std::to_string(i + 1);
  }



  unsigned int
  RhombicStructure::parameter_index(const std::string &name,
                                    const std::string &entry)
  {
    for (unsigned int i = 0; i < n_parameters; ++i)
      if (parameter_name(i) == name)
        return i;
    AssertThrow(false,
                ExcMessage(entry + ": '" + name + "' is not one of p1 ... p8"));
    return n_parameters;
  }



  void
  RhombicStructure::check() const
  {
    const auto r = ranges();
    // What the geometry allows; the sweep ranges are narrower.
    for (unsigned int i = 0; i < n_parameters; ++i)
      {
        const double lo = limits()[i][0], hi = limits()[i][1];
        AssertThrow(p[i] >= lo && p[i] <= hi,
                    ExcMessage("rhombic structure: " + parameter_name(i) +
                               " = " + std::to_string(p[i]) + " is outside [" +
                               std::to_string(lo) + ", " + std::to_string(hi) +
                               "] (sweep range [" + std::to_string(r[i][0]) +
                               ", " + std::to_string(r[i][1]) + "])"));
      }
    AssertThrow(p[0] + p[1] <= 0.99,
                ExcMessage("rhombic structure: p1 + p2 = " +
                           std::to_string(p[0] + p[1]) +
                           " puts node 2 outside its triangle (at most 0.99)"));
    AssertThrow(alpha >= M_PI / 8 - 1e-12 && alpha <= M_PI / 2 + 1e-12,
                ExcMessage("rhombic structure: the angle " +
                           std::to_string(alpha * 180 / M_PI) +
                           " degrees is outside [22.5, 90]"));
    AssertThrow(blending > 0 && blending <= 0.2,
                ExcMessage("rhombic structure: the blending " +
                           std::to_string(blending) + " is outside (0, 0.2]"));
  }



  Tensor<2, 2>
  RhombicStructure::cell_map() const
  {
    const double c = std::cos(alpha / 2), s = std::sin(alpha / 2);
    return Tensor<2, 2>({{c, c}, {-s, s}});
  }



  double
  RhombicStructure::corner_clearance() const
  {
    // F maps the reference corner (0, 0) to the origin. Without a
    // primitive near it, or beyond the level set's cut-off, it is far.
    const Point<2> corner(0, 0);
    const auto     g = graph<double>(p, {}, &corner);
    const double   v = g.value(corner);
    return v >= g.max_value() ? std::numeric_limits<double>::infinity() : v;
  }



  RhombicStructure
  RhombicStructure::mirrored() const
  {
    RhombicStructure m = *this;
    for (unsigned int i = 0; i < n_parameters; ++i)
      m.p[i] = p[mirror_partner(i)];
    return m;
  }



  unsigned int
  RhombicStructure::mirror_partner(const unsigned int i)
  {
    AssertIndexRange(i, n_parameters);
    constexpr std::array<unsigned int, n_parameters> partner = {
      {1, 0, 3, 2, 4, 5, 7, 6}};
    return partner[i];
  }



  bool
  RhombicStructure::clear_corner(const double clearance, const double lowest)
  {
    // The clearance falls as node 4 nears the corner; capped, so that a
    // far corner (an infinite clearance) still brackets the root.
    const auto excess = [&](const double p4) {
      RhombicStructure trial = *this;
      trial.p[3]             = p4;
      return std::min(trial.corner_clearance(), 1.) - clearance;
    };
    const double f_hi = excess(p[3]);
    if (f_hi >= 0 || p[3] <= lowest)
      return false;
    const double f_lo = excess(lowest);
    if (f_lo < 0)
      return false;
    // TOMS 748 keeps a bracket [clear, not clear]: its clear end to 1e-7.
    std::uintmax_t iterations = 60;
    const auto     bracket    = boost::math::tools::toms748_solve(
      excess,
      lowest,
      p[3],
      f_lo,
      f_hi,
      [](const double a, const double b) { return b - a <= 1e-7; },
      iterations);
    p[3] = bracket.first;
    return true;
  }



  std::array<Point<2>, 12>
  RhombicStructure::reference_nodes() const
  {
    const std::array<std::array<double, 2>, 4> base = {
      {{{0., -1.}},
       {{p[1] - p[0], -p[0] - p[1]}},
       {{-p[2], -p[2]}},
       {{p[3], -p[3]}}}};
    std::array<Point<2>, 12> nodes;
    unsigned int             n = 0;
    for (unsigned int t = 0; t < 4; ++t)
      for (unsigned int g = 0; g < 4; ++g)
        {
          // Nodes 3 and 4 lie on a mirror line: 2 images each.
          if ((t == 2 && (g == 1 || g == 2)) || (t == 3 && (g == 1 || g == 2)))
            continue;
          const auto u = symmetry(g, base[t]);
          nodes[n++]   = Point<2>(1 + u[0], 1 + u[1]);
        }
    return nodes;
  }



  template <typename Number>
  InflationGraph<Number>
  RhombicStructure::graph(const std::array<Number, n_parameters> &parameters,
                          const std::array<double, 4>            &side_radii,
                          const Point<2>                         *near) const
  {
    RhombicStructure checked = *this;
    for (unsigned int i = 0; i < n_parameters; ++i)
      checked.p[i] = val(parameters[i]);
    checked.check();
    const auto &q = parameters;
    // Node types 1..4 in the triangle OAB, O = 0, A = (-1, -1), B = (1, -1).
    const std::array<std::array<Number, 2>, 4> base = {
      {{{Number(0.), Number(-1.)}},
       {{q[1] - q[0], -q[0] - q[1]}},
       {{-q[2], -q[2]}},
       {{q[3], -q[3]}}}};
    const std::array<std::array<unsigned int, 2>, 4> quarter_edges = {
      {{{0, 1}}, {{1, 2}}, {{1, 3}}, {{2, 3}}}};

    const Tensor<2, 2> F = cell_map();
    // R's bounding box and the padding by which a primitive may still
    // matter inside it.
    double r_max = 0;
    for (unsigned int i = 4; i < 8; ++i)
      r_max = std::max(r_max, val(q[i]));
    for (const double r : side_radii)
      r_max = std::max(r_max, r);
    const double pad =
      r_max + 20 * InflationGraph<Number>::max_modulation * blending;
    Point<2> lo(1e30, 1e30), hi(-1e30, -1e30);
    for (const double a : {0., side})
      for (const double b : {0., side})
        for (unsigned int d = 0; d < 2; ++d)
          {
            const double x = F[d][0] * a + F[d][1] * b;
            lo[d]          = std::min(lo[d], x - pad);
            hi[d]          = std::max(hi[d], x + pad);
          }
    if (near)
      for (unsigned int d = 0; d < 2; ++d)
        lo[d] = (*near)[d] - pad, hi[d] = (*near)[d] + pad;

    using Vertex = typename InflationGraph<Number>::Vertex;
    std::vector<Vertex>                      vertices;
    std::vector<Point<2>>                    keys; // positions, for merging
    std::vector<std::array<unsigned int, 2>> edges;
    const auto vertex = [&](const std::array<Number, 2> &u_ref,
                            const Number                &radius) {
      std::array<Number, 2> x;
      for (unsigned int d = 0; d < 2; ++d)
        x[d] = F[d][0] * (u_ref[0] + 1.) + F[d][1] * (u_ref[1] + 1.);
      const Point<2> key(val(x[0]), val(x[1]));
      for (unsigned int i = 0; i < keys.size(); ++i)
        if (keys[i].distance(key) < 1e-10)
          return i;
      keys.push_back(key);
      // A side joint of this cell (reference (1, 0), (2, 1), (1, 2),
      // (0, 1)) may have a radius of its own.
      Number                        r = radius;
      const Point<2>                u(val(u_ref[0]) + 1., val(u_ref[1]) + 1.);
      const std::array<Point<2>, 4> midpoints = {
        {Point<2>(1, 0), Point<2>(2, 1), Point<2>(1, 2), Point<2>(0, 1)}};
      for (unsigned int k = 0; k < 4; ++k)
        if (side_radii[k] > 0 && u.distance(midpoints[k]) < 1e-10)
          r = Number(side_radii[k]);
      vertices.push_back(Vertex{x, r, blending});
      return static_cast<unsigned int>(vertices.size() - 1);
    };
    for (int i = -1; i <= 1; ++i)
      for (int j = -1; j <= 1; ++j)
        for (unsigned int g = 0; g < 4; ++g)
          for (const auto &[s, t] : quarter_edges)
            {
              std::array<Number, 2> ends[2];
              for (unsigned int k = 0; k < 2; ++k)
                {
                  ends[k] = symmetry(g, base[k == 0 ? s : t]);
                  ends[k][0] += side * i;
                  ends[k][1] += side * j;
                }
              // Keep the primitive if its box meets R's padded box.
              bool outside = false;
              for (unsigned int d = 0; d < 2 && !outside; ++d)
                {
                  double e_lo = 1e30, e_hi = -1e30;
                  for (unsigned int k = 0; k < 2; ++k)
                    {
                      const double x = F[d][0] * (val(ends[k][0]) + 1) +
                                       F[d][1] * (val(ends[k][1]) + 1);
                      e_lo = std::min(e_lo, x), e_hi = std::max(e_hi, x);
                    }
                  outside = e_hi < lo[d] || e_lo > hi[d];
                }
              if (outside)
                continue;
              const unsigned int a = vertex(ends[0], q[4 + s]);
              const unsigned int b = vertex(ends[1], q[4 + t]);
              if (std::find(edges.begin(),
                            edges.end(),
                            std::array<unsigned int, 2>{{a, b}}) ==
                    edges.end() &&
                  std::find(edges.begin(),
                            edges.end(),
                            std::array<unsigned int, 2>{{b, a}}) == edges.end())
                edges.push_back({{a, b}});
            }
    return InflationGraph<Number>(vertices, edges);
  }



  std::function<double(const Point<2> &)>
  RhombicStructure::level_set(const std::array<double, 4> &side_radii) const
  {
    for (const double r : side_radii)
      AssertThrow(r >= 0 && r <= 0.6,
                  ExcMessage("rhombic structure: a side joint radius " +
                             std::to_string(r) + " is outside [0, 0.6]"));
    const auto graph_ptr = std::make_shared<const InflationGraph<double>>(
      graph<double>(p, side_radii));
    const Tensor<2, 2> F = cell_map();
    return [graph_ptr, F](const Point<2> &x) {
      return graph_ptr->value(Point<2>(F * x));
    };
  }



  template InflationGraph<double>
  RhombicStructure::graph(const std::array<double, n_parameters> &,
                          const std::array<double, 4> &,
                          const Point<2> *) const;
  template InflationGraph<Sacado::Fad::DFad<double>>
  RhombicStructure::graph(
    const std::array<Sacado::Fad::DFad<double>, n_parameters> &,
    const std::array<double, 4> &,
    const Point<2> *) const;
} // namespace forma
