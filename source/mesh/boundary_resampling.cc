// Resampling of the boundary curves of a 2D mesh before it is remeshed:
// shape optimization stretches boundary segments in one place and crowds
// them in another, and a remesh that keeps them cannot mend the cells
// there (thesis Algorithm 1 remeshes the boundary too).

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <forma/mesh/boundary_resampling.h>

#include "resampling_check.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

namespace forma
{
  using namespace dealii;

  namespace
  {
    using Key = std::array<unsigned int, 3>; // inside, outside, boundary id

    Key
    key_of(const RegionBoundaries<2>::Facet &f)
    {
      return {{f.inside, f.outside, f.boundary_id}};
    }

    bool
    kept(const Key &key, const BoundaryResampling &o)
    {
      return o.keeps(key[0], key[1], key[2]);
    }

    // The turn of the polyline a-b-c at b, in [0, pi].
    double
    turn(const Point<2> &a, const Point<2> &b, const Point<2> &c)
    {
      const Tensor<1, 2> d = b - a, e = c - b;
      return std::atan2(std::abs(d[0] * e[1] - d[1] * e[0]), d * e);
    }

    bool
    lexicographically_less(const Point<2> &a, const Point<2> &b)
    {
      return a[0] < b[0] || (a[0] == b[0] && a[1] < b[1]);
    }

    // The size wanted at each vertex of the polyline p: `size`, or the
    // local segment length smoothed along it; no larger than a bend allows.
    std::vector<double>
    sizes(const std::vector<Point<2>> &p, const BoundaryResampling &o)
    {
      const unsigned int  n = p.size() - 1;
      std::vector<double> l(n), h(n + 1, o.size);
      for (unsigned int i = 0; i < n; ++i)
        l[i] = p[i].distance(p[i + 1]);
      // The mean length of the segments within `window` of a vertex: a
      // grading over many segments stays, a stretch over a few goes.
      const int window = 5;
      if (o.size <= 0)
        for (int i = 0; i <= int(n); ++i)
          {
            double sum = 0;
            int    k   = 0;
            for (int j = std::max(0, i - window);
                 j < std::min(int(n), i + window);
                 ++j, ++k)
              sum += l[j];
            h[i] = sum / k;
          }
      for (unsigned int i = 1; i < n; ++i)
        if (const double t = turn(p[i - 1], p[i], p[i + 1]); t > 0)
          h[i] = std::min(h[i], o.max_turn * (l[i - 1] + l[i]) / 2 / t);
      return h;
    }

    // Twice the area swept from the origin by the polyline a, x..., c.
    double
    swept_area(const Point<2>              &a,
               const std::vector<Point<2>> &x,
               const Point<2>              &c)
    {
      double     area = 0;
      Point<2>   last = a;
      const auto add  = [&](const Point<2> &y) {
        area += last[0] * y[1] - y[0] * last[1];
        last = y;
      };
      for (const auto &y : x)
        add(y);
      add(c);
      return area;
    }

    // Move the interior vertices x of the polyline a, x..., c along the
    // gradient of the enclosed area until it sweeps `target` again: points
    // on the chords of a bend cut its corners, and the regions would
    // shrink (or grow) with every remesh.
    void
    restore_area(const Point<2>        &a,
                 std::vector<Point<2>> &x,
                 const Point<2>        &c,
                 const double           target)
    {
      for (unsigned int iteration = 0; iteration < 3 && !x.empty(); ++iteration)
        {
          std::vector<Tensor<1, 2>> g(x.size());
          double                    gg = 0;
          for (unsigned int k = 0; k < x.size(); ++k)
            {
              const Point<2> &prev = k ? x[k - 1] : a;
              const Point<2> &next = k + 1 < x.size() ? x[k + 1] : c;
              g[k][0]              = next[1] - prev[1];
              g[k][1]              = prev[0] - next[0];
              gg += g[k] * g[k];
            }
          const double t = (target - swept_area(a, x, c)) / gg;
          for (unsigned int k = 0; k < x.size(); ++k)
            x[k] += t * g[k];
        }
    }

    // New interior vertices of the polyline p (its ends stay), evenly
    // spaced in the size function, enclosing the same area.
    std::vector<Point<2>>
    resample_piece(const std::vector<Point<2>> &p, const BoundaryResampling &o)
    {
      const auto          h = sizes(p, o);
      const unsigned int  n = p.size() - 1;
      std::vector<double> F(n + 1, 0.); // integral of ds / h
      for (unsigned int i = 0; i < n; ++i)
        F[i + 1] =
          F[i] + p[i].distance(p[i + 1]) * (1 / h[i] + 1 / h[i + 1]) / 2;
      // One interior vertex at least where there was one: it takes the area
      // back.
      const long segments = std::max(n > 1 ? 2L : 1L, std::lround(F[n]));
      std::vector<Point<2>> result;
      unsigned int          i = 0;
      for (long k = 1; k < segments; ++k)
        {
          const double t = F[n] * k / segments;
          while (i + 1 < n && F[i + 1] <= t)
            ++i;
          const double s = std::clamp((t - F[i]) / (F[i + 1] - F[i]), 0., 1.);
          result.push_back(p[i] + s * (p[i + 1] - p[i]));
        }
      const std::vector<Point<2>> inner(p.begin() + 1, p.end() - 1);
      restore_area(p[0], result, p[n], swept_area(p[0], inner, p[n]));
      return result;
    }

    // Resampled in the direction that depends on the geometry alone, so
    // the two sides of a cut interface, which run opposite ways, get the
    // same vertices.
    std::vector<Point<2>>
    resample_either_way(std::vector<Point<2>> p, const BoundaryResampling &o)
    {
      const unsigned int n       = p.size() - 1;
      const bool         reverse = p[0] == p[n] ?
                                     lexicographically_less(p[n - 1], p[1]) :
                                     lexicographically_less(p[n], p[0]);
      if (reverse)
        std::reverse(p.begin(), p.end());
      auto q = resample_piece(p, o);
      if (reverse)
        std::reverse(q.begin(), q.end());
      return q;
    }

    double
    orientation(const Point<2> &a, const Point<2> &b, const Point<2> &c)
    {
      return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    }

    // Throws if two facets cross (touching ends and the coincident sides of
    // a cut interface do not): resampling a curve that runs close to
    // another can cut through it.
    void
    check_no_crossings(const RegionBoundaries<2> &b)
    {
      const auto &x = b.vertices;
      for (unsigned int i = 0; i < b.facets.size(); ++i)
        for (unsigned int j = i + 1; j < b.facets.size(); ++j)
          {
            const auto  &p = b.facets[i].vertices, &q = b.facets[j].vertices;
            const double s1 = orientation(x[p[0]], x[p[1]], x[q[0]]),
                         s2 = orientation(x[p[0]], x[p[1]], x[q[1]]),
                         s3 = orientation(x[q[0]], x[q[1]], x[p[0]]),
                         s4 = orientation(x[q[0]], x[q[1]], x[p[1]]);
            AssertThrow(!(s1 * s2 < 0 && s3 * s4 < 0),
                        ExcMessage(
                          "boundary resampling: the resampled boundaries cross "
                          "near (" +
                          internal::fmt3(x[p[0]][0]) + ", " +
                          internal::fmt3(x[p[0]][1]) + ") (materials " +
                          std::to_string(b.facets[i].inside) + " and " +
                          std::to_string(b.facets[j].inside) +
                          "); lower Design/Remesh boundary size or Remesh "
                          "feature angle."));
          }
    }

    // The chains of facets of one key, as vertex lists (closed ones end at
    // their start), open ones first.
    std::vector<std::vector<unsigned int>>
    chains(std::map<unsigned int, unsigned int> next)
    {
      std::set<unsigned int> heads;
      for (const auto &e : next)
        heads.insert(e.first);
      for (const auto &e : next)
        heads.erase(e.second);
      std::vector<std::vector<unsigned int>> result;
      while (!next.empty())
        {
          unsigned int v = heads.empty() ? next.begin()->first : *heads.begin();
          heads.erase(v);
          std::vector<unsigned int> chain{v};
          for (auto it = next.find(v); it != next.end(); it = next.find(v))
            {
              v = it->second;
              next.erase(it);
              chain.push_back(v);
            }
          result.push_back(std::move(chain));
        }
      return result;
    }
  } // namespace



  std::map<types::material_id, double>
  region_areas(const RegionBoundaries<2> &b)
  {
    std::map<types::material_id, double> area;
    for (const auto &f : b.facets)
      {
        const auto &x  = b.vertices[f.vertices[0]],
                   &y  = b.vertices[f.vertices[1]];
        const double a = (x[0] * y[1] - y[0] * x[1]) / 2;
        area[f.inside] += a;
        if (f.outside != numbers::invalid_material_id)
          area[f.outside] -= a;
      }
    return area;
  }



  namespace
  {
    // Where the boundary cannot be resampled: corners (where keys meet or
    // chains end, where a chain turns by more than the feature angle) and
    // pinned vertices (of kept facets). The copies of a vertex on the two
    // sides of a cut interface share their flags, so both sides are cut
    // into the same pieces and a side whose twin is kept stays too.
    struct Corners
    {
      std::vector<bool> corner, pinned;
    };

    Corners
    find_corners(
      const RegionBoundaries<2>                                 &b,
      const std::map<Key, std::map<unsigned int, unsigned int>> &next,
      const BoundaryResampling                                  &o)
    {
      const unsigned int         n = b.vertices.size();
      Corners                    c{std::vector<bool>(n), std::vector<bool>(n)};
      std::vector<std::set<Key>> keys(n);
      std::vector<unsigned int>  degree(n);
      for (const auto &f : b.facets)
        for (const auto v : f.vertices)
          {
            keys[v].insert(key_of(f));
            ++degree[v];
            if (kept(key_of(f), o))
              c.pinned[v] = true;
          }
      for (unsigned int v = 0; v < n; ++v)
        c.corner[v] = c.pinned[v] || keys[v].size() != 1 || degree[v] != 2;
      for (const auto &[key, links] : next)
        for (const auto &chain : chains(links))
          {
            const unsigned int m = chain.size() - 1;
            const auto         x = [&](const unsigned int i) {
              return b.vertices[chain[i]];
            };
            for (unsigned int i = 1; i < m; ++i)
              if (turn(x(i - 1), x(i), x(i + 1)) > o.feature_angle)
                c.corner[chain[i]] = true;
            if (chain.front() == chain.back() &&
                turn(x(m - 1), x(0), x(1)) > o.feature_angle)
              c.corner[chain[0]] = true;
          }
      std::map<std::pair<double, double>, std::vector<unsigned int>> copies;
      for (unsigned int v = 0; v < n; ++v)
        copies[{b.vertices[v][0], b.vertices[v][1]}].push_back(v);
      for (const auto &[x, group] : copies)
        {
          bool corner = false, pinned = false;
          for (const auto v : group)
            corner = corner || c.corner[v], pinned = pinned || c.pinned[v];
          for (const auto v : group)
            c.corner[v] = corner, c.pinned[v] = pinned;
        }
      return c;
    }

    // A closed chain starts at a corner; without one, at its
    // lexicographically smallest vertex (the same on both sides of a cut).
    void
    start_at_a_corner(std::vector<unsigned int> &chain,
                      const RegionBoundaries<2> &b,
                      std::vector<bool>         &corner)
    {
      const unsigned int m     = chain.size() - 1;
      unsigned int       first = 0;
      for (unsigned int i = 0; i < m; ++i)
        if (corner[chain[i]] ||
            (!corner[chain[first]] &&
             lexicographically_less(b.vertices[chain[i]],
                                    b.vertices[chain[first]])))
          first = i;
      std::rotate(chain.begin(), chain.begin() + first, chain.end() - 1);
      chain.back()          = chain.front();
      corner[chain.front()] = true;
    }
  } // namespace



  RegionBoundaries<2>
  resample_boundaries(const RegionBoundaries<2> &b, const BoundaryResampling &o)
  {
    AssertThrow(o.size >= 0 && o.feature_angle > 0 && o.max_turn > 0,
                ExcMessage("boundary resampling: the size must be >= 0 and "
                           "the feature angle and the largest turn > 0."));
    std::map<Key, std::map<unsigned int, unsigned int>> next;
    for (const auto &f : b.facets)
      AssertThrow(next[key_of(f)].emplace(f.vertices[0], f.vertices[1]).second,
                  ExcMessage(
                    "boundary resampling: the boundary of material " +
                    std::to_string(f.inside) + " touches itself at vertex (" +
                    internal::fmt3(b.vertices[f.vertices[0]][0]) + ", " +
                    internal::fmt3(b.vertices[f.vertices[0]][1]) + ")."));
    auto [corner, pinned] = find_corners(b, next, o);

    RegionBoundaries<2>       result;
    std::vector<unsigned int> index(b.vertices.size(),
                                    numbers::invalid_unsigned_int);
    const auto                kept_vertex = [&](const unsigned int v) {
      if (index[v] == numbers::invalid_unsigned_int)
        {
          index[v] = result.vertices.size();
          result.vertices.push_back(b.vertices[v]);
        }
      return index[v];
    };
    for (const auto &[key, n] : next)
      for (auto chain : chains(n))
        {
          if (chain.front() == chain.back())
            start_at_a_corner(chain, b, corner);
          const unsigned int m = chain.size() - 1;
          AssertThrow(corner[chain[m]],
                      ExcMessage("boundary resampling: a boundary chain of "
                                 "material " +
                                 std::to_string(key[0]) +
                                 " is not oriented consistently."));
          const auto facet = [&](const unsigned int a, const unsigned int c) {
            result.facets.push_back({{{a, c}}, key[0], key[1], key[2]});
          };
          // Pieces between corners; a piece of one facet between pinned
          // vertices (a cut side whose twin is kept) stays as it is.
          for (unsigned int i = 0; i < m;)
            {
              unsigned int j = i + 1;
              while (!corner[chain[j]])
                ++j;
              unsigned int a = kept_vertex(chain[i]);
              if (kept(key, o) ||
                  (j == i + 1 && pinned[chain[i]] && pinned[chain[j]]))
                for (unsigned int k = i + 1; k <= j; ++k)
                  facet(kept_vertex(chain[k - 1]), kept_vertex(chain[k]));
              else
                {
                  std::vector<Point<2>> piece;
                  for (unsigned int k = i; k <= j; ++k)
                    piece.push_back(b.vertices[chain[k]]);
                  for (const auto &y : resample_either_way(piece, o))
                    {
                      result.vertices.push_back(y);
                      facet(a, result.vertices.size() - 1);
                      a = result.vertices.size() - 1;
                    }
                  facet(a, kept_vertex(chain[j]));
                }
              i = j;
            }
        }

    check_no_crossings(result);
    internal::check_region_change(region_areas(b),
                                  region_areas(result),
                                  o.max_area_change,
                                  "area",
                                  "lower the feature angle so that more "
                                  "bends stay as corners.");
    return result;
  }
} // namespace forma
