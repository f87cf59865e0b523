#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <forma/base/application.h>
#include <forma/base/records.h>
#include <forma/mesh/level_set_mesh.h>
#include <forma/mesh/mesh.h>
#include <forma/mesh/polygon_domain.h>

#include "gmsh_session.h"
#include "level_set_mesh_symmetry.h"
#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <optional>
#include <tuple>

namespace forma
{
  using namespace dealii;

  namespace
  {
    // A vertex of a traced boundary loop.
    struct LoopVertex
    {
      Point<2> x;
      bool     fixed = false; ///< box corner or where the contour meets a side
      bool     side_segment_follows = false; ///< the next segment is on a side
    };

    bool
    inside(const std::vector<Point<2>> &polygon, const Point<2> &x)
    {
      bool in = false;
      for (unsigned int i = 0, j = polygon.size() - 1; i < polygon.size();
           j = i++)
        if ((polygon[i][1] > x[1]) != (polygon[j][1] > x[1]) &&
            x[0] < polygon[j][0] + (polygon[i][0] - polygon[j][0]) *
                                     (x[1] - polygon[j][1]) /
                                     (polygon[i][1] - polygon[j][1]))
          in = !in;
      return in;
    }

    // Do the closed segments [a, b] and [c, d] intersect?
    bool
    segments_cross(const Point<2> &a,
                   const Point<2> &b,
                   const Point<2> &c,
                   const Point<2> &d)
    {
      const auto orient =
        [](const Point<2> &p, const Point<2> &q, const Point<2> &r) {
          const double v =
            (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
          return (v > 0) - (v < 0);
        };
      const int o1 = orient(a, b, c), o2 = orient(a, b, d),
                o3 = orient(c, d, a), o4 = orient(c, d, b);
      return o1 != o2 && o3 != o4 && o1 * o2 <= 0 && o3 * o4 <= 0;
    }

    /// Whether loop k crosses itself or any other loop (non-adjacent
    /// segments only), by a bounding-box sweep over all segments; `where`
    /// gets a point of a crossing of each crossed loop.
    std::vector<bool>
    crossing_loops(const std::vector<std::vector<Point<2>>> &loops,
                   std::vector<Point<2>>                    *where = nullptr)
    {
      struct Segment
      {
        double       x_lo, x_hi;
        unsigned int loop, index;
      };
      std::vector<Segment> segments;
      for (unsigned int k = 0; k < loops.size(); ++k)
        for (unsigned int i = 0; i < loops[k].size(); ++i)
          {
            const Point<2> &a = loops[k][i],
                           &b = loops[k][(i + 1) % loops[k].size()];
            segments.push_back(
              {std::min(a[0], b[0]), std::max(a[0], b[0]), k, i});
          }
      std::sort(segments.begin(),
                segments.end(),
                [](const Segment &s, const Segment &t) {
                  return s.x_lo < t.x_lo;
                });
      std::vector<bool> crossed(loops.size(), false);
      if (where)
        where->assign(loops.size(), Point<2>());
      for (unsigned int i = 0; i < segments.size(); ++i)
        for (unsigned int j = i + 1;
             j < segments.size() && segments[j].x_lo <= segments[i].x_hi;
             ++j)
          {
            const Segment     &s = segments[i], &t = segments[j];
            const auto        &L = loops[s.loop], &M = loops[t.loop];
            const unsigned int n = L.size();
            if (s.loop == t.loop &&
                (s.index == t.index || (s.index + 1) % n == t.index ||
                 (t.index + 1) % n == s.index))
              continue; // neighbours share a vertex
            if (segments_cross(L[s.index],
                               L[(s.index + 1) % n],
                               M[t.index],
                               M[(t.index + 1) % M.size()]))
              {
                crossed[s.loop] = crossed[t.loop] = true;
                if (where)
                  (*where)[s.loop] = (*where)[t.loop] = M[t.index];
              }
          }
      return crossed;
    }


    /**
     * The material's boundary loops in the box by marching squares on a
     * periodic grid: contour segments (material on their left) and the
     * parts of the box's sides in the material, counterclockwise, chained.
     *
     * `half`: the box is the lower half y <= L_1 / 2 of a periodic cell
     * whose level set is symmetric under the rotation by pi about the
     * cell's center. Periodic in x only; on the sides y = 0 and y = L_1 / 2
     * (each its own image, mirrored about x = L_0 / 2) the samples and
     * crossings of the right half are the mirror images of the left's, so
     * the two sides' points are exactly symmetric.
     */
    class Tracer
    {
    public:
      Tracer(const std::function<double(const Point<2> &)> &phi,
             const Point<2>                                &box,
             const unsigned int                             grid,
             const bool                                     half = false)
        : phi(phi)
        , box(box)
        , half(half)
      {
        const double longer = std::max(box[0], box[1]);
        n[0]                = std::max(
          4u, static_cast<unsigned int>(std::lround(grid * box[0] / longer)));
        n[1] = std::max(
          4u, static_cast<unsigned int>(std::lround(grid * box[1] / longer)));
        if (half)
          n[0] += n[0] % 2; // x = L_0 / 2 is a grid line
        values.resize((n[0] + 1) * (n[1] + 1));
        const double tiny = 1e-12 * longer;
        for (unsigned int j = 0; j <= n[1]; ++j)
          for (unsigned int i = 0; i <= n[0]; ++i)
            {
              double v;
              if (i == n[0])
                v = value(0, j); // periodic: the same samples
              else if (j == n[1] && !half)
                v = value(i, 0);
              else if (half && (j == 0 || j == n[1]) && 2 * i > n[0])
                v = value(n[0] - i, j);
              else
                v = phi(node(i, j));
              // No sample exactly on the contour: a zero counts as void.
              values[index(i, j)] = (v == 0 ? tiny : v);
              AssertThrow(std::isfinite(v),
                          ExcMessage("the level set is not finite at (" +
                                     std::to_string(node(i, j)[0]) + ", " +
                                     std::to_string(node(i, j)[1]) + ")"));
            }
      }

      std::vector<std::vector<LoopVertex>>
      loops()
      {
        for (unsigned int j = 0; j < n[1]; ++j)
          for (unsigned int i = 0; i < n[0]; ++i)
            add_cell(i, j);
        add_box_sides();
        std::vector<std::vector<LoopVertex>> result;
        std::map<std::int64_t, bool>         visited;
        for (const auto &[start, ignored] : next)
          {
            if (visited[start])
              continue;
            std::vector<LoopVertex> loop;
            std::int64_t            k = start;
            do
              {
                visited[k] = true;
                LoopVertex v;
                v.x                    = position(k);
                v.fixed                = is_fixed(k);
                v.side_segment_follows = side_segment.count(k) > 0;
                loop.push_back(v);
                const auto it = next.find(k);
                AssertThrow(it != next.end(),
                            ExcMessage("marching squares left an open "
                                       "contour (internal error)"));
                k = it->second;
            } while (k != start);
            result.push_back(std::move(loop));
          }
        return result;
      }

    private:
      enum Kind : std::int64_t
      {
        grid_node  = 0,
        horizontal = 1, // crossing on the edge (i, j) - (i + 1, j)
        vertical   = 2  // crossing on the edge (i, j) - (i, j + 1)
      };

      std::int64_t
      key(const Kind kind, const unsigned int i, const unsigned int j) const
      {
        return (static_cast<std::int64_t>(kind) * (n[0] + 1) + i) * (n[1] + 1) +
               j;
      }

      unsigned int
      index(const unsigned int i, const unsigned int j) const
      {
        return j * (n[0] + 1) + i;
      }

      double
      value(const unsigned int i, const unsigned int j) const
      {
        return values[index(i, j)];
      }

      Point<2>
      node(const unsigned int i, const unsigned int j) const
      {
        return Point<2>(i == n[0] ? box[0] : box[0] * i / n[0],
                        j == n[1] ? box[1] : box[1] * j / n[1]);
      }

      bool
      material(const unsigned int i, const unsigned int j) const
      {
        return value(i, j) < 0;
      }

      // The root of phi on a grid edge: secant steps bracketed by the
      // samples (Illinois), computed on the wrapped edge so that opposite
      // sides get the same points.
      Point<2>
      crossing(const Kind kind, const unsigned int i, const unsigned int j)
      {
        if (half && kind == horizontal && (j == 0 || j == n[1]) &&
            2 * i >= n[0])
          {
            Point<2> x = crossing(kind, n[0] - 1 - i, j);
            x[0]       = box[0] - x[0];
            return x;
          }
        const unsigned int wi = (kind == vertical && i == n[0]) ? 0 : i;
        const unsigned int wj =
          (kind == horizontal && j == n[1] && !half) ? 0 : j;
        const std::int64_t k  = key(kind, wi, wj);
        auto               it = crossings.find(k);
        if (it == crossings.end())
          {
            const unsigned int i1 = wi + (kind == horizontal),
                               j1 = wj + (kind == vertical);
            const Point<2> a = node(wi, wj), b = node(i1, j1);
            double ta = 0, tb = 1, fa = value(wi, wj), fb = value(i1, j1);
            int    side = 0;
            double t    = fa / (fa - fb);
            for (unsigned int step = 0; step < 30; ++step)
              {
                t              = (ta * fb - tb * fa) / (fb - fa);
                const double f = phi(a + t * (b - a));
                if (std::abs(f) < 1e-13 * std::max(box[0], box[1]))
                  break;
                if ((f < 0) == (fa < 0))
                  {
                    ta = t, fa = f;
                    if (side == -1)
                      fb /= 2;
                    side = -1;
                  }
                else
                  {
                    tb = t, fb = f;
                    if (side == 1)
                      fa /= 2;
                    side = 1;
                  }
                if (tb - ta < 1e-12)
                  break;
              }
            it = crossings.insert({k, a + t * (b - a)}).first;
          }
        Point<2> x = it->second;
        if (wi != i)
          x[0] = box[0];
        if (wj != j)
          x[1] = box[1];
        return x;
      }

      Point<2>
      position(const std::int64_t k)
      {
        const unsigned int j = k % (n[1] + 1);
        const unsigned int i = (k / (n[1] + 1)) % (n[0] + 1);
        const Kind kind      = static_cast<Kind>(k / ((n[0] + 1) * (n[1] + 1)));
        return kind == grid_node ? node(i, j) : crossing(kind, i, j);
      }

      bool
      is_fixed(const std::int64_t k) const
      {
        const unsigned int j = k % (n[1] + 1);
        const unsigned int i = (k / (n[1] + 1)) % (n[0] + 1);
        const Kind kind      = static_cast<Kind>(k / ((n[0] + 1) * (n[1] + 1)));
        const bool on_x_side = (i == 0 || i == n[0]);
        const bool on_y_side = (j == 0 || j == n[1]);
        if (kind == grid_node)
          return on_x_side && on_y_side; // a corner
        // A crossing on a side: the contour meets the box there.
        return (kind == vertical && on_x_side) ||
               (kind == horizontal && on_y_side);
      }

      void
      link(const std::int64_t from, const std::int64_t to)
      {
        AssertThrow(next.insert({from, to}).second,
                    ExcMessage("marching squares: a point with two outgoing "
                               "segments (internal error)"));
      }

      void
      add_cell(const unsigned int i, const unsigned int j)
      {
        // Corners and edges counterclockwise; edge e joins corner e, e + 1.
        const std::array<std::array<unsigned int, 2>, 4> c = {
          {{{i, j}}, {{i + 1, j}}, {{i + 1, j + 1}}, {{i, j + 1}}}};
        const std::array<std::int64_t, 4> edge = {{key(horizontal, i, j),
                                                   key(vertical, i + 1, j),
                                                   key(horizontal, i, j + 1),
                                                   key(vertical, i, j)}};
        std::vector<std::int64_t>         exits, entries; // along the walk
        std::vector<unsigned int>         exit_at, entry_at;
        for (unsigned int e = 0; e < 4; ++e)
          {
            const bool m0 = material(c[e][0], c[e][1]),
                       m1 = material(c[(e + 1) % 4][0], c[(e + 1) % 4][1]);
            if (m0 && !m1)
              exits.push_back(edge[e]), exit_at.push_back(e);
            else if (!m0 && m1)
              entries.push_back(edge[e]), entry_at.push_back(e);
          }
        if (exits.empty())
          return;
        if (exits.size() == 1)
          {
            link(exits[0], entries[0]);
            return;
          }
        // Saddle: the center decides whether the material connects across.
        double center = 0;
        for (const auto &corner : c)
          center += value(corner[0], corner[1]) / 4;
        for (unsigned int a = 0; a < 2; ++a)
          {
            // The entry next along the walk (the material connects through
            // the center) or the other one (separated corners).
            const unsigned int after = (entry_at[0] + 4 - exit_at[a]) % 4 <
                                           (entry_at[1] + 4 - exit_at[a]) % 4 ?
                                         0 :
                                         1;
            link(exits[a], entries[center < 0 ? after : 1 - after]);
          }
      }

      // The box's sides counterclockwise, split at the grid nodes.
      void
      add_box_sides()
      {
        std::vector<std::array<unsigned int, 2>> ring;
        for (unsigned int i = 0; i < n[0]; ++i)
          ring.push_back({{i, 0}});
        for (unsigned int j = 0; j < n[1]; ++j)
          ring.push_back({{n[0], j}});
        for (unsigned int i = n[0]; i > 0; --i)
          ring.push_back({{i, n[1]}});
        for (unsigned int j = n[1]; j > 0; --j)
          ring.push_back({{0, j}});
        for (unsigned int r = 0; r < ring.size(); ++r)
          {
            const auto &a = ring[r], &b = ring[(r + 1) % ring.size()];
            const bool  ma = material(a[0], a[1]), mb = material(b[0], b[1]);
            const auto  ka = key(grid_node, a[0], a[1]),
                       kb  = key(grid_node, b[0], b[1]);
            std::int64_t kc;
            if (a[1] == b[1])
              kc = key(horizontal, std::min(a[0], b[0]), a[1]);
            else
              kc = key(vertical, a[0], std::min(a[1], b[1]));
            if (ma && mb)
              link(ka, kb), side_segment.insert({ka, true});
            else if (ma)
              link(ka, kc), side_segment.insert({ka, true});
            else if (mb)
              link(kc, kb), side_segment.insert({kc, true});
          }
      }

      const std::function<double(const Point<2> &)> &phi;
      const Point<2>                                 box;
      const bool                                     half;
      std::array<unsigned int, 2>                    n;
      std::vector<double>                            values;
      std::map<std::int64_t, Point<2>>               crossings;
      std::map<std::int64_t, std::int64_t>           next;
      std::map<std::int64_t, bool>                   side_segment;
    };


    // Newton steps along the gradient onto phi = 0, kept in the box.
    Point<2>
    project(const std::function<double(const Point<2> &)> &phi,
            Point<2>                                       x,
            const Point<2>                                &box,
            const double                                   step_limit)
    {
      const double   h  = 1e-7 * std::max(box[0], box[1]);
      const Point<2> x0 = x;
      for (unsigned int it = 0; it < 6; ++it)
        {
          const double f = phi(x);
          Tensor<1, 2> g;
          for (unsigned int d = 0; d < 2; ++d)
            {
              Point<2> a = x, b = x;
              a[d] -= h, b[d] += h;
              g[d] = (phi(b) - phi(a)) / (2 * h);
            }
          if (g.norm_square() == 0)
            break;
          const Tensor<1, 2> dx = -f * g / g.norm_square();
          x += dx;
          if (dx.norm() < 1e-12 * std::max(box[0], box[1]))
            break;
        }
      // A contour point never moves further than the tracing error; keep
      // clear of the sides so that no unmatched node lands on one.
      if (x.distance(x0) > step_limit)
        x = x0;
      for (unsigned int d = 0; d < 2; ++d)
        x[d] = std::clamp(x[d], 1e-6 * box[d], box[d] * (1 - 1e-6));
      return x;
    }


    // Resample a loop: sides and contour runs between fixed vertices,
    // boundary_size apart; contour vertices projected onto phi = 0.
    // joint_size > 0: the side y = box_1 is the joint of a symmetric half,
    // sampled that far apart.
    std::vector<Point<2>>
    resample(const std::vector<LoopVertex>                 &loop,
             const std::function<double(const Point<2> &)> &phi,
             const Point<2>                                &box,
             const double                                   h,
             const double                                   grid_spacing,
             const double                                   joint_size = 0)
    {
      std::vector<unsigned int> fixed;
      for (unsigned int i = 0; i < loop.size(); ++i)
        if (loop[i].fixed)
          fixed.push_back(i);
      std::vector<Point<2>> result;
      const auto            sample_run = [&](const std::vector<Point<2>> &run,
                                  const bool                   on_side,
                                  const bool                   closed) {
        // run: the polyline from its first to its last point (closed: back
        // to the first); emits all its points but the last.
        std::vector<double> s(1, 0.);
        for (unsigned int i = 1; i < run.size(); ++i)
          s.push_back(s.back() + run[i].distance(run[i - 1]));
        const double       length = s.back();
        const unsigned int pieces =
          std::max(closed ? 3u : 1u,
                   static_cast<unsigned int>(std::ceil(length / h - 1e-9)));
        if (on_side)
          {
            // Straight: equal pieces, the same on the opposite side. The
            // joint y = box_1 of a symmetric half is inside the cell: no
            // stresses concentrate there, so interior elements.
            const bool on_joint = joint_size > 0 && run.front()[1] == box[1] &&
                                  run.back()[1] == box[1];
            const unsigned int pieces =
              std::max(1u,
                       static_cast<unsigned int>(
                         std::ceil(run.front().distance(run.back()) /
                                     (on_joint ? joint_size : h) -
                                   1e-9)));
            for (unsigned int k = 0; k < pieces; ++k)
              result.push_back(run.front() + (static_cast<double>(k) / pieces) *
                                               (run.back() - run.front()));
            return;
          }
        result.push_back(closed && !on_side ?
                           project(phi, run[0], box, 2 * grid_spacing) :
                           run[0]);
        unsigned int seg = 0;
        for (unsigned int k = 1; k < pieces; ++k)
          {
            const double t = length * k / pieces;
            while (seg + 2 < run.size() && s[seg + 1] < t)
              ++seg;
            const double w =
              (t - s[seg]) / std::max(s[seg + 1] - s[seg], 1e-300);
            const Point<2> x = run[seg] + w * (run[seg + 1] - run[seg]);
            result.push_back(on_side ? x :
                                       project(phi, x, box, 2 * grid_spacing));
          }
      };
      if (fixed.empty())
        {
          std::vector<Point<2>> run;
          for (const auto &v : loop)
            run.push_back(v.x);
          run.push_back(loop[0].x);
          sample_run(run, false, true);
          return result;
        }
      for (unsigned int f = 0; f < fixed.size(); ++f)
        {
          const unsigned int    a = fixed[f], b = fixed[(f + 1) % fixed.size()];
          std::vector<Point<2>> run;
          for (unsigned int i = a;; i = (i + 1) % loop.size())
            {
              run.push_back(loop[i].x);
              if (i != a && i == b)
                break;
              if (fixed.size() == 1 && run.size() > loop.size())
                break;
            }
          sample_run(run, loop[a].side_segment_follows, false);
        }
      return result;
    }


    internal::GmshTriangles
    generate(const std::vector<std::vector<Point<2>>> &outer,
             const std::vector<std::vector<Point<2>>> &holes,
             const std::vector<int>                   &hole_owner,
             const LevelSetMeshParameters             &parameters,
             const int                                 algorithm)
    {
      namespace geo = gmsh::model::geo;
      std::vector<int> lines_all;
      const auto       add_loop = [&](const std::vector<Point<2>> &loop) {
        std::vector<int> points, lines;
        for (const auto &x : loop)
          points.push_back(
            geo::addPoint(x[0], x[1], 0, parameters.boundary_size));
        for (unsigned int i = 0; i < points.size(); ++i)
          {
            lines.push_back(
              geo::addLine(points[i], points[(i + 1) % points.size()]));
            lines_all.push_back(lines.back());
          }
        return geo::addCurveLoop(lines);
      };
      std::vector<int> surfaces;
      for (unsigned int o = 0; o < outer.size(); ++o)
        {
          std::vector<int> loops = {add_loop(outer[o])};
          for (unsigned int k = 0; k < holes.size(); ++k)
            if (hole_owner[k] == static_cast<int>(o))
              loops.push_back(add_loop(holes[k]));
          surfaces.push_back(geo::addPlaneSurface(loops));
        }
      // One element per boundary segment: the nodes on opposite sides are
      // the resampled points, which match.
      for (const int l : lines_all)
        geo::mesh::setTransfiniteCurve(l, 2);
      geo::synchronize();
      gmsh::model::addPhysicalGroup(2, surfaces, 1);
      gmsh::option::setNumber("Mesh.MeshSizeMax", parameters.size);
      gmsh::option::setNumber("Mesh.MeshSizeMin", 0);
      gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 1);
      gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
      gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 0);
      gmsh::option::setNumber("Mesh.Algorithm", algorithm);
      gmsh::model::mesh::generate(2);
      internal::gmsh_check_generated(2, "level set mesh");
      return internal::gmsh_triangles();
    }
  } // namespace



  namespace
  {
    /// The material's contours of one tracing: its pieces, its holes and
    /// the piece each hole lies in.
    struct Contours
    {
      std::vector<std::vector<Point<2>>> outer, holes;
      std::vector<int>                   owner;
    };



    /**
     * One level set meshed, for both meshers: with `periodic`, material
     * loops must reach the box's sides; without, the material must stay
     * inside the box and every loop with positive area is a piece of it.
     * Where resampled contours cross, the material is thickened around
     * the crossing and traced again.
     */
    class LevelSetMesher
    {
    public:
      LevelSetMesher(const std::function<double(const Point<2> &)> &phi_in,
                     const Point<2>                                &box,
                     const Tensor<1, 2>                            &origin,
                     const bool                                     periodic,
                     const LevelSetMeshParameters                  &parameters,
                     const std::string                             &context);

      LevelSetMesher(const LevelSetMesher &) = delete;

      /// Meshed on the root of comm, read on every rank.
      void
      mesh(Triangulation<2> &tria, const MPI_Comm comm, LevelSetMeshInfo *info);

    private:
      void
      check_arguments() const;

      /// phi_in with the material thickened around `thickened` (box
      /// coordinates; the nearest periodic copy).
      double
      thickened_value(const Point<2> &x) const;

      /// A point in the user's coordinates, for messages.
      std::string
      at(const Point<2> &x) const;

      /// The half stands for the whole cell only if phi has the symmetry:
      /// spot-checked on a 16 x 16 grid of points off the sampling grid.
      void
      check_symmetry() const;

      /// The traced and resampled loops, sorted into pieces and holes.
      Contours
      trace();

      /// Resampled contours of features near the boundary element size may
      /// touch: a small hole that does is filled, anything else is
      /// thickened if allowed (false: the crossings are in `retry`), or an
      /// error that names the cause.
      bool
      resolve_crossings(Contours &c);

      /// Each hole's innermost piece (islands sit in holes).
      void
      find_owners(Contours &c) const;

      void
      keep_largest_piece(Contours &c);

      /// Frontal-Delaunay, and plain Delaunay if that cannot recover a
      /// boundary edge (it happens at near-touching contours), each on a
      /// fresh model.
      internal::GmshTriangles
      triangulate(const Contours &c) const;

      /// One tracing and meshing; where contours cross and thickenings are
      /// left it returns nothing and puts the crossings in `retry`.
      internal::GmshTriangles
      attempt();

      /// Thicken at the crossings of `retry` (and at their rotated images).
      void
      thicken();

      const std::function<double(const Point<2> &)> &phi_in;
      const Point<2>                                 box;
      const Tensor<1, 2>                             origin;
      const bool                                     periodic;
      const LevelSetMeshParameters                  &parameters;
      const std::string                             &context;
      /// Symmetric cells: trace and mesh the lower half, then add its copy
      /// rotated by pi; a piece traced there stands for two.
      const bool         symmetric;
      const Point<2>     traced_box;
      const unsigned int copies;
      const double       depth, radius;
      /// A std::function: the tracer keeps a reference to it.
      const std::function<double(const Point<2> &)> phi;
      std::vector<Point<2>>                         thickened, retry;
      LevelSetMeshInfo                              local_info;
    };



    LevelSetMesher::LevelSetMesher(
      const std::function<double(const Point<2> &)> &phi_in,
      const Point<2>                                &box,
      const Tensor<1, 2>                            &origin,
      const bool                                     periodic,
      const LevelSetMeshParameters                  &parameters,
      const std::string                             &context)
      : phi_in(phi_in)
      , box(box)
      , origin(origin)
      , periodic(periodic)
      , parameters(parameters)
      , context(context)
      , symmetric(parameters.centrally_symmetric)
      , traced_box(symmetric ? Point<2>(box[0], box[1] / 2) : box)
      , copies(symmetric ? 2 : 1)
      , depth(parameters.boundary_size)
      , radius(4 * parameters.boundary_size)
      , phi([this](const Point<2> &x) { return thickened_value(x); })
    {
      check_arguments();
      check_symmetry();
    }



    void
    LevelSetMesher::check_arguments() const
    {
      AssertThrow(box[0] > 0 && box[1] > 0,
                  ExcMessage(context + ": the box must have positive sides"));
      AssertThrow(parameters.grid >= 8 && parameters.grid <= 8192,
                  ExcMessage(context + ": the marching squares grid " +
                             std::to_string(parameters.grid) +
                             " is outside [8, 8192]"));
      AssertThrow(parameters.size > 0 && parameters.boundary_size > 0 &&
                    parameters.boundary_size <= parameters.size &&
                    parameters.size < std::min(box[0], box[1]),
                  ExcMessage(context +
                             ": need 0 < boundary size <= element "
                             "size < the box (boundary size " +
                             std::to_string(parameters.boundary_size) +
                             ", element size " +
                             std::to_string(parameters.size) + ")"));
      AssertThrow(!periodic || !parameters.largest_piece_only,
                  ExcMessage(context + ": a periodic structure may be "
                                       "several pieces in the cell; "
                                       "largest_piece_only is for objects"));
      AssertThrow(periodic || !parameters.centrally_symmetric,
                  ExcMessage(context + ": centrally_symmetric is for "
                                       "periodic cells"));
    }



    double
    LevelSetMesher::thickened_value(const Point<2> &x) const
    {
      double value = phi_in(x);
      for (const Point<2> &c : thickened)
        {
          Tensor<1, 2> d = x - c;
          if (periodic)
            for (unsigned int i = 0; i < 2; ++i)
              d[i] -= box[i] * std::round(d[i] / box[i]);
          const double t = d.norm_square() / (radius * radius);
          if (t < 1)
            value -= depth * (1 - t) * (1 - t);
        }
      return value;
    }



    std::string
    LevelSetMesher::at(const Point<2> &x) const
    {
      return "(" + sig(x[0] + origin[0], 4) + ", " + sig(x[1] + origin[1], 4) +
             ")";
    }



    void
    LevelSetMesher::check_symmetry() const
    {
      for (unsigned int i = 0; symmetric && i < 16; ++i)
        for (unsigned int j = 0; j < 16; ++j)
          {
            const Point<2> x(box[0] * (i + 0.37) / 16,
                             box[1] * (j + 0.61) / 16);
            AssertThrow(std::abs(phi_in(x) - phi_in(Point<2>(box - x))) <=
                          1e-8 * std::max(box[0], box[1]),
                        ExcMessage(context +
                                   ": the level set is not symmetric under "
                                   "the rotation by 180 degrees about the "
                                   "cell's center (at " +
                                   at(x) +
                                   "), so the cell cannot be meshed as half "
                                   "plus its rotated copy"));
          }
    }



    Contours
    LevelSetMesher::trace()
    {
      // The half's grid spacing is the whole cell's.
      const unsigned int n = static_cast<unsigned int>(
        std::lround(parameters.grid * std::max(traced_box[0], traced_box[1]) /
                    std::max(box[0], box[1])));
      Tracer       tracer(phi, traced_box, n, symmetric);
      const double spacing = std::max(box[0], box[1]) / parameters.grid;
      Contours     c;
      for (const auto &loop : tracer.loops())
        {
          const bool touches =
            std::any_of(loop.begin(), loop.end(), [](const LoopVertex &v) {
              return v.fixed;
            });
          std::vector<Point<2>> polygon =
            resample(loop,
                     phi,
                     traced_box,
                     parameters.boundary_size,
                     spacing,
                     symmetric ? parameters.size : 0);
          const double a = signed_area(polygon);
          AssertThrow(periodic || !touches,
                      ExcMessage(context + ": the material reaches the "
                                           "sides of its box"));
          if (touches || (!periodic && a > 0))
            c.outer.push_back(std::move(polygon));
          else if (a > 0)
            local_info.dropped_islands += copies;
          else if (-a < std::pow(parameters.boundary_size, 2))
            local_info.dropped_holes += copies;
          else
            c.holes.push_back(std::move(polygon));
        }
      AssertThrow(!c.outer.empty(),
                  ExcMessage(context +
                             (periodic ?
                                ": the material does not reach the sides "
                                "of the cell, so it cannot form a "
                                "periodic structure" :
                                ": there is no material to mesh")));
      return c;
    }



    bool
    LevelSetMesher::resolve_crossings(Contours &c)
    {
      auto                              &outer = c.outer, &holes = c.holes;
      std::vector<std::vector<Point<2>>> all = outer;
      all.insert(all.end(), holes.begin(), holes.end());
      std::vector<Point<2>>   where, where_outer;
      const std::vector<bool> crossed = crossing_loops(all, &where);
      const std::vector<bool> outer_crossed =
        crossing_loops(outer, &where_outer);
      const double large_hole = 16 * std::pow(parameters.boundary_size, 2);
      // A piece crossed by itself or a piece, or a hole crossed that is too
      // large to fill: all thickened at once.
      for (unsigned int k = 0; k < all.size(); ++k)
        if (thickened.size() + copies * (retry.size() + 1) <=
            parameters.max_thickenings)
          if (k < outer.size() ?
                outer_crossed[k] :
                crossed[k] && -signed_area(all[k]) >= large_hole)
            retry.push_back(k < outer.size() ? where_outer[k] : where[k]);
      if (!retry.empty())
        return false;
      for (unsigned int k = 0; k < outer.size(); ++k)
        AssertThrow(!outer_crossed[k],
                    ExcMessage(context +
                               ": the resampled material boundary "
                               "crosses itself near " +
                               at(where_outer[k]) +
                               ": a gap or a joint is thinner than the "
                               "boundary element size " +
                               sig(parameters.boundary_size, 3)));
      std::vector<std::vector<Point<2>>> kept;
      for (unsigned int k = 0; k < holes.size(); ++k)
        if (!crossed[outer.size() + k])
          kept.push_back(std::move(holes[k]));
        else
          {
            AssertThrow(-signed_area(holes[k]) < large_hole,
                        ExcMessage(context +
                                   ": a hole's resampled boundary crosses "
                                   "the material's boundary near " +
                                   at(where[outer.size() + k]) +
                                   ": a wall is thinner than the boundary "
                                   "element size " +
                                   sig(parameters.boundary_size, 3)));
            local_info.dropped_holes += copies;
          }
      holes = std::move(kept);
      return true;
    }



    void
    LevelSetMesher::find_owners(Contours &c) const
    {
      c.owner.assign(c.holes.size(), -1);
      for (unsigned int k = 0; k < c.holes.size(); ++k)
        {
          double smallest = 1e300;
          for (unsigned int o = 0; o < c.outer.size(); ++o)
            if (inside(c.outer[o], c.holes[k][0]) &&
                std::abs(signed_area(c.outer[o])) < smallest)
              {
                c.owner[k] = o;
                smallest   = std::abs(signed_area(c.outer[o]));
              }
          AssertThrow(c.owner[k] >= 0,
                      ExcMessage(context +
                                 ": a hole of the material lies in no "
                                 "piece of it (inconsistent contours)"));
        }
    }



    void
    LevelSetMesher::keep_largest_piece(Contours &c)
    {
      if (c.outer.size() <= 1)
        return;
      unsigned int largest = 0;
      for (unsigned int o = 1; o < c.outer.size(); ++o)
        if (std::abs(signed_area(c.outer[o])) >
            std::abs(signed_area(c.outer[largest])))
          largest = o;
      std::vector<std::vector<Point<2>>> kept;
      for (unsigned int k = 0; k < c.holes.size(); ++k)
        if (c.owner[k] == static_cast<int>(largest))
          kept.push_back(std::move(c.holes[k]));
      local_info.dropped_islands += c.outer.size() - 1;
      c.outer = {std::move(c.outer[largest])};
      c.holes = std::move(kept);
      c.owner.assign(c.holes.size(), 0);
    }



    internal::GmshTriangles
    LevelSetMesher::triangulate(const Contours &c) const
    {
      for (const int algorithm : {6, 5})
        try
          {
            if (algorithm != 6)
              {
                gmsh::clear();
                gmsh::model::add("forma-level-set-mesh");
              }
            return generate(c.outer, c.holes, c.owner, parameters, algorithm);
          }
        catch (const std::string &) // what the Gmsh API throws
          {
            if (algorithm == 5)
              throw;
          }
        catch (const std::exception &e)
          {
            AssertThrow(algorithm != 5,
                        ExcMessage(error_message(e) +
                                   " (is a gap or a joint of the structure "
                                   "thinner than the boundary element "
                                   "size?)"));
          }
      return internal::GmshTriangles();
    }



    internal::GmshTriangles
    LevelSetMesher::attempt()
    {
      local_info             = LevelSetMeshInfo();
      local_info.thickenings = thickened.size();
      Contours c             = trace();
      if (!resolve_crossings(c))
        return internal::GmshTriangles();
      find_owners(c);
      if (parameters.largest_piece_only)
        keep_largest_piece(c);
      return triangulate(c);
    }



    void
    LevelSetMesher::thicken()
    {
      for (const Point<2> &c : retry)
        {
          thickened.push_back(c);
          // And its image, unless that overlaps it (a point near a center
          // of the rotation would be thickened twice).
          Tensor<1, 2> d = 2 * c - box;
          for (unsigned int i = 0; i < 2; ++i)
            d[i] -= box[i] * std::round(d[i] / box[i]);
          if (symmetric && d.norm() > radius)
            thickened.emplace_back(box[0] - c[0], box[1] - c[1]);
        }
    }



    void
    LevelSetMesher::mesh(Triangulation<2> &tria,
                         const MPI_Comm    comm,
                         LevelSetMeshInfo *info)
    {
      internal::GmshTriangles mesh =
        internal::gmsh_on_root(comm, "forma-level-set-mesh", context, [&]() {
          for (;;)
            {
              retry.clear();
              internal::GmshTriangles result = attempt();
              if (retry.empty())
                return result;
              thicken(); // before any Gmsh model is made
            }
        });
      if (symmetric)
        {
          internal::GmshTriangles whole;
          internal::join_rotated_copy(
            mesh, box, whole.vertices, whole.cells, local_info.dropped_islands);
          AssertThrow(!whole.cells.empty(),
                      ExcMessage(context +
                                 ": the material does not reach the sides "
                                 "of the cell, so it cannot form a "
                                 "periodic structure"));
          mesh = std::move(whole);
        }
      Triangulation<2> read;
      read.create_triangulation(mesh.vertices, mesh.cells, SubCellData());
      double area = 0;
      for (const auto &cell : read.active_cell_iterators())
        {
          cell->set_material_id(0);
          area += cell->measure();
        }
      check_mesh_validity(read, context + " mesh");
      local_info.boundary_loops = internal::count_boundary_loops(read);
      tria.clear();
      tria.copy_triangulation(read);
      if (info)
        {
          *info      = Utilities::MPI::broadcast(comm, local_info);
          info->area = area;
        }
    }



    void
    mesh_level_set(const std::function<double(const Point<2> &)> &phi,
                   const Point<2>                                &box,
                   const Tensor<1, 2>                            &origin,
                   const bool                                     periodic,
                   const LevelSetMeshParameters                  &parameters,
                   Triangulation<2>                              &tria,
                   const MPI_Comm                                 comm,
                   LevelSetMeshInfo                              *info,
                   const std::string                             &context)
    {
      LevelSetMesher(phi, box, origin, periodic, parameters, context)
        .mesh(tria, comm, info);
    }
  } // namespace



  void
  periodic_level_set_mesh(const std::function<double(const Point<2> &)> &phi,
                          const Point<2>                                &box,
                          const LevelSetMeshParameters &parameters,
                          Triangulation<2>             &tria,
                          const MPI_Comm                comm,
                          LevelSetMeshInfo             *info,
                          const std::string            &context)
  {
    mesh_level_set(
      phi, box, Tensor<1, 2>(), true, parameters, tria, comm, info, context);
  }



  void
  level_set_mesh(const std::function<double(const Point<2> &)> &phi,
                 const Point<2>                                &lower,
                 const Point<2>                                &upper,
                 const LevelSetMeshParameters                  &parameters,
                 Triangulation<2>                              &tria,
                 const MPI_Comm                                 comm,
                 LevelSetMeshInfo                              *info,
                 const std::string                             &context)
  {
    const Tensor<1, 2> shift = lower;
    mesh_level_set([&](const Point<2> &x) { return phi(x + shift); },
                   Point<2>(upper - lower),
                   shift,
                   false,
                   parameters,
                   tria,
                   comm,
                   info,
                   context);
    GridTools::shift(shift, tria);
  }
} // namespace forma
