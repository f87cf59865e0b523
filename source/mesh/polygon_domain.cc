#include <deal.II/base/exceptions.h>
#include <deal.II/grid/tria.h>

#include <forma/mesh/polygon_domain.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace forma
{
  using namespace dealii;

  namespace
  {
    double
    distance_to_segment(const Point<2> &x, const Point<2> &a, const Point<2> &b)
    {
      const Tensor<1, 2> e  = b - a;
      const double       ee = e * e;
      const double       t = ee > 0 ? std::clamp((x - a) * e / ee, 0., 1.) : 0.;
      return x.distance(a + t * e);
    }

    /// Whether the ray from x in +x direction crosses the side a-b.
    bool
    crosses(const Point<2> &x, const Point<2> &a, const Point<2> &b)
    {
      return (a[1] > x[1]) != (b[1] > x[1]) &&
             x[0] < a[0] + (x[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
    }
  } // namespace



  double
  signed_area(const std::vector<Point<2>> &polygon)
  {
    double a = 0;
    for (unsigned int i = 0; i < polygon.size(); ++i)
      {
        const Point<2> &p = polygon[i], &q = polygon[(i + 1) % polygon.size()];
        a += p[0] * q[1] - q[0] * p[1];
      }
    return a / 2;
  }



  PolygonDomain::PolygonDomain(const std::vector<Segment> &input,
                               const bool                  classify_holes)
    : segments(input)
  {
    AssertThrow(!segments.empty(),
                ExcMessage("polygon domain: the boundary has no sides"));
    lo = hi = segments[0].a;
    for (const Segment &s : segments)
      for (const Point<2> &p : {s.a, s.b})
        for (unsigned int d = 0; d < 2; ++d)
          {
            lo[d] = std::min(lo[d], p[d]);
            hi[d] = std::max(hi[d], p[d]);
          }
    // End points are matched on a grid far finer than any side.
    const double tolerance = 1e-9 * std::max(hi[0] - lo[0], hi[1] - lo[1]);
    const auto   key       = [&](const Point<2> &p) {
      return std::make_pair(std::llround((p[0] - lo[0]) / tolerance),
                            std::llround((p[1] - lo[1]) / tolerance));
    };
    std::multimap<std::pair<long long, long long>, unsigned int> at;
    for (unsigned int s = 0; s < segments.size(); ++s)
      {
        at.emplace(key(segments[s].a), s);
        at.emplace(key(segments[s].b), s);
      }
    std::vector<bool> used(segments.size(), false);
    for (unsigned int first = 0; first < segments.size(); ++first)
      {
        if (used[first])
          continue;
        Loop loop;
        used[first]    = true;
        Point<2> start = segments[first].a, current = segments[first].b;
        loop.vertices.push_back(start);
        loop.ids.push_back(segments[first].id);
        while (key(current) != key(start))
          {
            loop.vertices.push_back(current);
            const auto   range = at.equal_range(key(current));
            unsigned int next  = segments.size();
            for (auto it = range.first; it != range.second; ++it)
              if (!used[it->second])
                {
                  next = it->second;
                  break;
                }
            AssertThrow(next < segments.size(),
                        ExcMessage("polygon domain: the boundary is not "
                                   "closed at (" +
                                   std::to_string(current[0]) + ", " +
                                   std::to_string(current[1]) + ")"));
            used[next] = true;
            loop.ids.push_back(segments[next].id);
            current = key(segments[next].a) == key(current) ? segments[next].b :
                                                              segments[next].a;
          }
        loops.push_back(loop);
      }
    // A loop inside an odd number of others bounds a hole.
    for (Loop &l : loops)
      if (classify_holes)
        {
          unsigned int depth = 0;
          for (const Loop &m : loops)
            if (&m != &l)
              {
                bool            in = false;
                const Point<2> &x  = l.vertices[0];
                for (unsigned int k = 0; k < m.vertices.size(); ++k)
                  {
                    const Point<2> &a = m.vertices[k],
                                   &b = m.vertices[(k + 1) % m.vertices.size()];
                    in ^= crosses(x, a, b);
                  }
                depth += in;
              }
          l.hole = depth % 2 == 1;
        }
  }



  PolygonDomain
  PolygonDomain::boundary_of(const Triangulation<2, 2> &tria,
                             const bool                 classify_holes)
  {
    std::vector<Segment> segments;
    for (const auto &cell : tria.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          segments.push_back({cell->face(f)->vertex(0),
                              cell->face(f)->vertex(1),
                              cell->face(f)->boundary_id()});
    return PolygonDomain(segments, classify_holes);
  }



  bool
  PolygonDomain::inside(const Point<2> &x) const
  {
    bool in = false;
    for (const Segment &s : segments)
      in ^= crosses(x, s.a, s.b);
    return in;
  }



  double
  PolygonDomain::signed_distance(const Point<2> &x) const
  {
    double d = 1e300;
    for (const Segment &s : segments)
      d = std::min(d, distance_to_segment(x, s.a, s.b));
    return inside(x) ? -d : d;
  }



  Point<2>
  PolygonDomain::point_inside_near(const Point<2> &x, const double depth) const
  {
    double best = 1e300;
    for (const Segment &s : segments)
      best = std::min(best, distance_to_segment(x, s.a, s.b));
    // The closest sides (two at a vertex): the sum of their inward normals
    // bisects the corner, inside whether it is convex or reflex.
    const double tolerance = 1e-12 * std::max(hi[0] - lo[0], hi[1] - lo[1]);
    Point<2>     p;
    Tensor<1, 2> direction;
    for (const Segment &s : segments)
      if (distance_to_segment(x, s.a, s.b) <= best + tolerance)
        {
          const Tensor<1, 2> e = s.b - s.a;
          const double       t = std::clamp((x - s.a) * e / (e * e), 0., 1.);
          p                    = s.a + t * e;
          Tensor<1, 2>   n     = Tensor<1, 2>({-e[1], e[0]}) / e.norm();
          const Point<2> m     = s.a + 0.5 * e;
          if (!inside(m + 1e-6 * e.norm() * n))
            n = -n;
          direction += n;
        }
    return direction.norm() > 0 ? p + depth * direction / direction.norm() : p;
  }



  types::boundary_id
  PolygonDomain::boundary_id(const Point<2>          &x,
                             const double             tolerance,
                             const types::boundary_id otherwise) const
  {
    types::boundary_id id   = otherwise;
    double             best = tolerance;
    for (const Segment &s : segments)
      {
        const double d = distance_to_segment(x, s.a, s.b);
        if (d < best)
          {
            best = d;
            id   = s.id;
          }
      }
    return id;
  }



  double
  PolygonDomain::length(const types::boundary_id id) const
  {
    double l = 0;
    for (const Segment &s : segments)
      if (s.id == id)
        l += s.a.distance(s.b);
    return l;
  }
} // namespace forma
