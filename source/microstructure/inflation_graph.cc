#include <deal.II/base/exceptions.h>

#include <forma/microstructure/inflation_graph.h>

#include "ad_value.h"

#include <algorithm>
#include <cmath>
#include <limits>

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
  } // namespace



  template <typename Number>
  InflationGraph<Number>::InflationGraph(
    const std::vector<Vertex>                      &vertices,
    const std::vector<std::array<unsigned int, 2>> &edges)
    : vertices(vertices)
    , edges(edges)
    , incident(vertices.size())
    , joint_blending(vertices.size())
  {
    using std::acos;
    using std::sqrt;
    for (unsigned int e = 0; e < edges.size(); ++e)
      for (const unsigned int v : edges[e])
        {
          AssertThrow(v < vertices.size(),
                      ExcMessage("inflation graph: edge " + std::to_string(e) +
                                 " refers to a missing vertex"));
          incident[v].push_back(e);
        }
    for (unsigned int i = 0; i < vertices.size(); ++i)
      {
        AssertThrow(val(vertices[i].radius) > 0 && vertices[i].blending > 0,
                    ExcMessage("inflation graph: vertex " + std::to_string(i) +
                               " needs a positive radius and blending"));
        // The smallest angle between two incident edges (differentiable in
        // the vertex data: the fillet widths move with the geometry).
        std::vector<std::array<Number, 2>> directions;
        for (const unsigned int e : incident[i])
          {
            const Vertex &other =
              this->vertices[edges[e][0] == i ? edges[e][1] : edges[e][0]];
            const Number ux = other.position[0] - vertices[i].position[0],
                         uy = other.position[1] - vertices[i].position[1];
            const Number norm =
              std::sqrt(val(ux) * val(ux) + val(uy) * val(uy)) > 0 ?
                Number(sqrt(ux * ux + uy * uy)) :
                Number(1.);
            directions.push_back({{ux / norm, uy / norm}});
          }
        Number theta = M_PI;
        for (unsigned int a = 0; a < directions.size(); ++a)
          for (unsigned int b = a + 1; b < directions.size(); ++b)
            {
              const Number c = directions[a][0] * directions[b][0] +
                               directions[a][1] * directions[b][1];
              const Number t = std::abs(val(c)) < 1 - 1e-12 ?
                                 Number(acos(c)) :
                                 Number(val(c) > 0 ? 0. : M_PI);
              if (val(t) < val(theta))
                theta = t;
            }
        const double m = 0.5 * M_PI / std::max(val(theta), 1e-3);
        joint_blending[i] =
          vertices[i].blending *
          (m <= 1 ? Number(1.) :
                    (m >= max_modulation ? Number(max_modulation) :
                                           Number(0.5 * M_PI / theta)));
      }

    // Buckets: what is near each part of the plane.
    double s_max = 0, r_max = 0;
    for (unsigned int i = 0; i < vertices.size(); ++i)
      {
        s_max = std::max(s_max, val(joint_blending[i]));
        r_max = std::max(r_max, val(vertices[i].radius));
      }
    if (edges.empty())
      return; // no material: value() is +infinity everywhere
    reach = std::max(20 * s_max, 1e-3 * r_max);
    box   = bounding_box();
    for (unsigned int d = 0; d < 2; ++d)
      {
        box[0][d] -= reach;
        box[1][d] += reach;
        n_buckets[d] = std::clamp(static_cast<unsigned int>(
                                    (box[1][d] - box[0][d]) / (0.5 * reach)),
                                  1u,
                                  64u);
      }
    bucket_edges.assign(n_buckets[0] * n_buckets[1], {});
    bucket_joints.assign(n_buckets[0] * n_buckets[1], {});
    for (unsigned int e = 0; e < edges.size(); ++e)
      {
        std::array<unsigned int, 2> lo, hi;
        for (unsigned int d = 0; d < 2; ++d)
          {
            double a = 1e300, b = -1e300;
            for (const unsigned int v : edges[e])
              {
                const double r = val(vertices[v].radius) + reach;
                a              = std::min(a, val(vertices[v].position[d]) - r);
                b              = std::max(b, val(vertices[v].position[d]) + r);
              }
            const double h = (box[1][d] - box[0][d]) / n_buckets[d];
            lo[d]          = static_cast<unsigned int>(
              std::clamp((a - box[0][d]) / h, 0., n_buckets[d] - 1.));
            hi[d] = static_cast<unsigned int>(
              std::clamp((b - box[0][d]) / h, 0., n_buckets[d] - 1.));
          }
        for (unsigned int j = lo[1]; j <= hi[1]; ++j)
          for (unsigned int i = lo[0]; i <= hi[0]; ++i)
            {
              auto &list = bucket_edges[j * n_buckets[0] + i];
              list.push_back(e);
              auto &joints = bucket_joints[j * n_buckets[0] + i];
              for (const unsigned int v : edges[e])
                if (std::find(joints.begin(), joints.end(), v) == joints.end())
                  joints.push_back(v);
            }
      }
  }



  template <typename Number>
  Number
  InflationGraph<Number>::edge_distance(const unsigned int      e,
                                        const dealii::Point<2> &x) const
  {
    using std::abs;
    using std::sqrt;
    const Vertex &A = vertices[edges[e][0]], &B = vertices[edges[e][1]];
    const Number  ax = x[0] - A.position[0], ay = x[1] - A.position[1];
    const Number  bx = x[0] - B.position[0], by = x[1] - B.position[1];
    const Number  da = sqrt(ax * ax + ay * ay) - A.radius;
    const Number  db = sqrt(bx * bx + by * by) - B.radius;
    const Number  lx = B.position[0] - A.position[0],
                 ly  = B.position[1] - A.position[1];
    const Number h   = sqrt(lx * lx + ly * ly);
    // One disk inside the other: their hull is the larger disk.
    if (val(h) <= std::abs(val(A.radius) - val(B.radius)) + 1e-14)
      return val(da) < val(db) ? da : db;
    const Number t = (ax * lx + ay * ly) / h;    // along the axis
    const Number q = abs(ax * ly - ay * lx) / h; // off the axis, >= 0
    const Number s = (A.radius - B.radius) / h;  // sine of the taper
    const Number c = sqrt(1. - s * s);
    const Number k = c * t - s * q; // along the tangent, from A's contact
    if (val(k) < 0)
      return da;
    if (val(k) > val(h * c))
      return db;
    return c * q + s * t - A.radius;
  }



  template <typename Number>
  Number
  InflationGraph<Number>::value(const dealii::Point<2> &x) const
  {
    using std::exp;
    using std::log;
    if (edges.empty())
      return Number(std::numeric_limits<double>::infinity());
    std::array<int, 2> b;
    for (unsigned int d = 0; d < 2; ++d)
      {
        b[d] = static_cast<int>(std::floor((x[d] - box[0][d]) * n_buckets[d] /
                                           (box[1][d] - box[0][d])));
        if (b[d] < 0 || b[d] >= static_cast<int>(n_buckets[d]))
          return Number(reach);
      }
    const unsigned int bucket = b[1] * n_buckets[0] + b[0];
    const auto        &near   = bucket_edges[bucket];
    if (near.empty())
      return Number(reach);
    // Distances of the edges near x; the others count as beyond reach.
    // Scratch reused between calls (this runs per sample point).
    thread_local std::vector<Number> d;
    thread_local std::vector<char>   is_near;
    d.resize(edges.size());
    is_near.assign(edges.size(), 0);
    unsigned int nearest = near[0];
    for (const unsigned int e : near)
      {
        d[e]       = edge_distance(e, x);
        is_near[e] = true;
        if (val(d[e]) < val(d[nearest]))
          nearest = e;
      }
    if (val(d[nearest]) >= reach)
      return Number(reach);
    // The joints; the two lowest are merged.
    Number J_a = d[nearest], J_b = d[nearest];
    double lowest = std::numeric_limits<double>::max(), second = lowest;
    for (const unsigned int i : bucket_joints[bucket])
      {
        Number       J     = d[nearest];
        unsigned int count = 0;
        double       m     = std::numeric_limits<double>::max();
        for (const unsigned int e : incident[i])
          if (is_near[e])
            {
              m = std::min(m, val(d[e]));
              if (count++ == 0)
                J = d[e];
            }
        if (count == 0)
          continue;
        if (count > 1)
          {
            const Number s = joint_blending[i];
            // Shifted by the minimum so that exp never underflows to 0.
            Number sum = 0.;
            for (const unsigned int e : incident[i])
              if (is_near[e])
                sum += exp(-(d[e] - m) / s);
            J = m - s * log(sum);
          }
        if (val(J) < lowest)
          {
            second = lowest, J_b = J_a;
            lowest = val(J), J_a = J;
          }
        else if (val(J) < second)
          second = val(J), J_b = J;
      }
    if (second == std::numeric_limits<double>::max())
      return J_a;
    const Number k = 2. * (d[nearest] - J_a);
    if (val(k) <= 1e-14 || second - lowest >= val(k))
      return J_a;
    const Number g = (k - (J_b - J_a)) / k;
    return J_a - 0.25 * g * g * k;
  }



  template <typename Number>
  std::array<Point<2>, 2>
  InflationGraph<Number>::bounding_box() const
  {
    const double inf = std::numeric_limits<double>::max();
    Point<2>     lo(inf, inf), hi(-inf, -inf);
    double       pad = 0;
    for (const auto &s : joint_blending)
      pad = std::max(pad, val(s) * std::log(8.));
    for (const auto &edge : edges)
      for (const unsigned int v : edge)
        for (unsigned int d = 0; d < 2; ++d)
          {
            const double r = val(vertices[v].radius) + pad;
            lo[d]          = std::min(lo[d], val(vertices[v].position[d]) - r);
            hi[d]          = std::max(hi[d], val(vertices[v].position[d]) + r);
          }
    return {{lo, hi}};
  }



  template class InflationGraph<double>;
  template class InflationGraph<Sacado::Fad::DFad<double>>;
} // namespace forma
