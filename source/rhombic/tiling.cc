#include <forma/rhombic/quad_mesh_optimization.h>
#include <forma/rhombic/tiling.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    Quad
    quad_of_cell(const Triangulation<2, 2>::active_cell_iterator &cell)
    {
      Quad v;
      for (unsigned int k = 0; k < 4; ++k)
        v[k] = cell->vertex(k);
      return v;
    }



    std::vector<Quad>
    quads_of(const Triangulation<2, 2> &tria)
    {
      std::vector<Quad> quads(tria.n_active_cells());
      for (const auto &cell : tria.active_cell_iterators())
        quads[cell->active_cell_index()] = quad_of_cell(cell);
      return quads;
    }



    Point<2>
    bilinear(const Quad &v, const double s, const double t)
    {
      return Point<2>((1 - s) * (1 - t) * v[0] + s * (1 - t) * v[1] +
                      (1 - s) * t * v[2] + s * t * v[3]);
    }



    std::vector<Quad>
    subdivide(const std::vector<Quad>   &quads,
              const unsigned int         n,
              std::vector<unsigned int> &parent)
    {
      std::vector<Quad> children;
      parent.clear();
      for (unsigned int c = 0; c < quads.size(); ++c)
        {
          const Quad &v  = quads[c];
          const auto  at = [&](const unsigned int i, const unsigned int j) {
            return bilinear(v, double(i) / n, double(j) / n);
          };
          for (unsigned int j = 0; j < n; ++j)
            for (unsigned int i = 0; i < n; ++i)
              {
                children.push_back(
                  {{at(i, j), at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)}});
                parent.push_back(c);
              }
        }
      return children;
    }



    Quad
    acute_first(const Quad &v)
    {
      // Squares keep their numbering (round-off must not turn a structure
      // by 90 degrees against its neighbours: with p1 != p2 it is chiral).
      if (fit_rhombus(v).angle <= M_PI / 2 + 1e-9)
        return v;
      // Start at vertex 1, keeping the orientation: 1, 3, 0, 2.
      return {{v[1], v[3], v[0], v[2]}};
    }



    bool
    reference_point(const Quad &v, const Point<2> &x, Point<2> &xi)
    {
      xi = Point<2>(0.5, 0.5);
      for (unsigned int it = 0; it < 12; ++it)
        {
          const double       s = xi[0], t = xi[1];
          const Point<2>     f   = bilinear(v, s, t);
          const Tensor<1, 2> ds  = (1 - t) * (v[1] - v[0]) + t * (v[3] - v[2]);
          const Tensor<1, 2> dt  = (1 - s) * (v[2] - v[0]) + s * (v[3] - v[1]);
          const double       det = ds[0] * dt[1] - ds[1] * dt[0];
          if (!(std::abs(det) > 0))
            return false;
          const Tensor<1, 2> r = x - f;
          xi[0] += (r[0] * dt[1] - r[1] * dt[0]) / det;
          xi[1] += (ds[0] * r[1] - ds[1] * r[0]) / det;
        }
      return xi[0] >= -1e-9 && xi[0] <= 1 + 1e-9 && xi[1] >= -1e-9 &&
             xi[1] <= 1 + 1e-9;
    }



    TiledObject::TiledObject(const std::vector<Quad>             &input,
                             const std::vector<RhombicStructure> &structures,
                             const Tensor<1, 2>                  &period,
                             const bool                           merge_joints,
                             const bool                           orient)
    {
      AssertThrow(input.size() == structures.size() && !input.empty(),
                  ExcMessage("tiling: one structure per quad"));
      double h = 0;
      for (unsigned int c = 0; c < input.size(); ++c)
        h += std::sqrt(fit_rhombus(input[c]).area) / input.size();
      pad = 0.05 * h;
      lo = hi = input[0][0];
      for (const Quad &q : input)
        for (const Point<2> &p : q)
          for (unsigned int d = 0; d < 2; ++d)
            {
              lo[d] = std::min(lo[d], p[d]);
              hi[d] = std::max(hi[d], p[d]);
            }
      const bool          periodic = period.norm() > 0;
      std::vector<double> radius; // p5 per quad, and its copies
      for (int i = periodic ? -1 : 0; i <= (periodic ? 1 : 0); ++i)
        for (int j = periodic ? -1 : 0; j <= (periodic ? 1 : 0); ++j)
          for (unsigned int c = 0; c < input.size(); ++c)
            {
              Quad q = orient ? acute_first(input[c]) : input[c];
              for (Point<2> &p : q)
                p += Tensor<1, 2>({i * period[0], j * period[1]});
              quads.push_back(q);
              half_size.push_back(0.5 * std::sqrt(fit_rhombus(q).area));
              radius.push_back(structures[c].p[4]);
            }

      // The sides y = 0, x = 2, y = 2, x = 0 of the reference square are
      // the quad's sides v0 v1, v1 v3, v2 v3, v0 v2; neighbours (also
      // across the period) share a side's midpoint.
      constexpr unsigned int side_vertices[4][2] = {{0, 1},
                                                    {1, 3},
                                                    {2, 3},
                                                    {0, 2}};
      const auto             key                 = [&](const Point<2> &x) {
        return std::make_pair(std::llround(x[0] / (1e-7 * h)),
                              std::llround(x[1] / (1e-7 * h)));
      };
      std::multimap<std::pair<long long, long long>, unsigned int> sides;
      for (unsigned int c = 0; c < quads.size(); ++c)
        for (unsigned int k = 0; k < 4; ++k)
          sides.emplace(key(Point<2>(0.5 * (quads[c][side_vertices[k][0]] +
                                            quads[c][side_vertices[k][1]]))),
                        c);
      std::vector<std::array<double, 4>> side_radii(quads.size(),
                                                    {{0, 0, 0, 0}});
      for (unsigned int c = 0; c < quads.size(); ++c)
        for (unsigned int k = 0; k < 4; ++k)
          {
            const auto range = sides.equal_range(
              key(Point<2>(0.5 * (quads[c][side_vertices[k][0]] +
                                  quads[c][side_vertices[k][1]]))));
            for (auto it = range.first; it != range.second; ++it)
              if (it->second != c)
                {
                  // Physical radii: cells of different sizes with the
                  // same p5 do not match either.
                  const unsigned int n  = it->second;
                  const double       rc = half_size[c] * radius[c],
                               rn       = half_size[n] * radius[n],
                               l        = 0.5 * (half_size[c] + half_size[n]);
                  largest_joint_mismatch =
                    std::max(largest_joint_mismatch, std::abs(rc - rn) / l);
                  // The average, in c's reference units (within p5's
                  // range).
                  if (merge_joints && std::abs(rc - rn) > 1e-9 * l)
                    side_radii[c][k] =
                      std::clamp(0.5 * (rc + rn) / half_size[c], 0.01, 0.6);
                }
          }
      for (unsigned int c = 0; c < quads.size(); ++c)
        phi.push_back(
          structures[c % structures.size()].level_set(side_radii[c]));
      // The bucket grid covers the box and a pad around it; periodic copies
      // further out are never asked for.
      box_lo               = lo - Tensor<1, 2>({pad, pad});
      box_hi               = hi + Tensor<1, 2>({pad, pad});
      const unsigned int n = std::max<unsigned int>(
        1, static_cast<unsigned int>(std::sqrt(double(input.size()))));
      nb = {{n, n}};
      buckets.resize(n * n);
      for (unsigned int c = 0; c < quads.size(); ++c)
        {
          std::array<double, 2> a{{1e300, 1e300}}, b{{-1e300, -1e300}};
          for (const Point<2> &p : quads[c])
            for (unsigned int d = 0; d < 2; ++d)
              {
                a[d] = std::min(a[d], p[d] - pad);
                b[d] = std::max(b[d], p[d] + pad);
              }
          if (b[0] < box_lo[0] || a[0] > box_hi[0] || b[1] < box_lo[1] ||
              a[1] > box_hi[1])
            continue;
          for (unsigned int i = bucket(0, a[0]); i <= bucket(0, b[0]); ++i)
            for (unsigned int j = bucket(1, a[1]); j <= bucket(1, b[1]); ++j)
              buckets[i * nb[1] + j].push_back(c);
        }
    }



    unsigned int
    TiledObject::bucket(const unsigned int d, const double v) const
    {
      const double t =
        (v - box_lo[d]) / std::max(box_hi[d] - box_lo[d], 1e-300);
      return std::min<unsigned int>(nb[d] - 1,
                                    static_cast<unsigned int>(std::max(0., t) *
                                                              nb[d]));
    }



    double
    TiledObject::operator()(const Point<2> &x) const
    {
      double value = pad;
      if (x[0] < box_lo[0] || x[0] > box_hi[0] || x[1] < box_lo[1] ||
          x[1] > box_hi[1])
        return value;
      for (const unsigned int c :
           buckets[bucket(0, x[0]) * nb[1] + bucket(1, x[1])])
        {
          const Quad &v = quads[c];
          // Signed distance to the quad (around it: 0, 1, 3, 2).
          double s = -1e300;
          for (const auto &[i, j] :
               {std::pair<unsigned int, unsigned int>{0, 1},
                {1, 3},
                {3, 2},
                {2, 0}})
            {
              const Tensor<1, 2> e = v[j] - v[i];
              s                    = std::max(s,
                           (e[1] * (x[0] - v[i][0]) - e[0] * (x[1] - v[i][1])) /
                             e.norm());
            }
          if (s >= value)
            continue;
          Point<2> xi;
          reference_point(v, x, xi);
          // A seam shared by two quads (or the side of a periodic box)
          // counts as material where either structure has material there:
          // a sample exactly on it would otherwise read 0, i.e. void.
          value =
            std::min(value,
                     std::max(half_size[c] *
                                phi[c](Point<2>(RhombicStructure::side * xi)),
                              s - 1e-9 * pad));
        }
      return value;
    }
  } // namespace rhombic
} // namespace forma
