#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/grid/tria.h>

#include <forma/base/application.h>
#include <forma/mesh/mesh.h>
#include <forma/mesh/periodic_phase_mesh.h>
#include <forma/microstructure/raster.h>

#include "gmsh_session.h"
#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <map>
#include <tuple>

namespace forma
{
  using namespace dealii;

  namespace
  {
    const std::string context = "periodic phase mesh";

    // The curves on the box side x_d = value, with their extent along the
    // other direction.
    std::vector<std::pair<std::array<double, 2>, int>>
    side_curves(const unsigned int d, const double value, const double eps)
    {
      double lo[3] = {-eps, -eps, -eps}, hi[3] = {1e30, 1e30, eps};
      lo[d] = value - eps, hi[d] = value + eps;
      gmsh::vectorpair curves;
      gmsh::model::getEntitiesInBoundingBox(
        lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], curves, 1);
      std::vector<std::pair<std::array<double, 2>, int>> result;
      for (const auto &c : curves)
        {
          double b[6];
          gmsh::model::getBoundingBox(
            1, c.second, b[0], b[1], b[2], b[3], b[4], b[5]);
          result.push_back({{{b[1 - d], b[4 - d]}}, c.second});
        }
      std::sort(result.begin(), result.end());
      return result;
    }

    ConvexPolygon
    clipped_to_box(const std::vector<Point<2>> &polygon, const Point<2> &box)
    {
      ConvexPolygon p = polygon;
      p               = clip(p, Point<2>(), Tensor<1, 2>({-1., 0.}));
      p               = clip(p, Point<2>(), Tensor<1, 2>({0., -1.}));
      p               = clip(p, box, Tensor<1, 2>({1., 0.}));
      return clip(p, box, Tensor<1, 2>({0., 1.}));
    }

    /// Which sides of direction d the point is within `tolerance` of:
    /// -1 none, 0 the lower one, 1 the upper one.
    int
    near_side(const Point<2>    &v,
              const Point<2>    &box,
              const unsigned int d,
              const double       tolerance)
    {
      return std::abs(v[d]) < tolerance          ? 0 :
             std::abs(v[d] - box[d]) < tolerance ? 1 :
                                                   -1;
    }

    /**
     * Where the polygons meet each pair of opposite sides (vertices within
     * `tolerance` of a side, corners aside, by their coordinate along it),
     * merged over both sides and clustered: a cluster grows while the gaps
     * stay within `tolerance`, and is represented by its first value.
     * Periodic images meet the sides at the same places up to round-off,
     * but a vertex of one image can land within a micron of another's; the
     * box's sides are split at every breakpoint, so both get the same curves.
     */
    std::array<std::vector<std::pair<double, double>>, 2>
    side_breakpoints(const std::vector<ConvexPolygon> &polygons,
                     const Point<2>                   &box,
                     const double                      tolerance)
    {
      std::array<std::vector<std::pair<double, double>>, 2> result;
      for (unsigned int d = 0; d < 2; ++d)
        {
          std::vector<double> t;
          for (const auto &p : polygons)
            for (const auto &v : p)
              if (near_side(v, box, d, tolerance) >= 0 &&
                  near_side(v, box, 1 - d, tolerance) < 0)
                t.push_back(v[1 - d]);
          std::sort(t.begin(), t.end());
          for (unsigned int i = 0; i < t.size(); ++i)
            if (i == 0 || t[i] - t[i - 1] > tolerance)
              result[d].emplace_back(t[i], t[i]); // (first, last) value
            else
              result[d].back().second = t[i];
        }
      return result;
    }

    /// `p` with vertices within `tolerance` of a side moved onto it and,
    /// along it, onto their breakpoint (near two sides: onto the corner);
    /// repeated vertices removed.
    ConvexPolygon
    snapped_to_sides(
      const ConvexPolygon                                         &p,
      const Point<2>                                              &box,
      const std::array<std::vector<std::pair<double, double>>, 2> &breakpoints,
      const double                                                 snap,
      const double                                                 tolerance)
    {
      ConvexPolygon result;
      for (Point<2> v : p)
        {
          const std::array<int, 2> near = {
            {near_side(v, box, 0, tolerance), near_side(v, box, 1, tolerance)}};
          for (unsigned int d = 0; d < 2; ++d)
            if (near[d] >= 0)
              {
                v[d] = near[d] == 0 ? 0. : box[d];
                if (near[1 - d] >= 0)
                  continue; // a corner: the other direction snaps it too
                const auto &b = breakpoints[d];
                const auto  it =
                  std::upper_bound(b.begin(),
                                   b.end(),
                                   v[1 - d],
                                   [](const double                     x,
                                      const std::pair<double, double> &c) {
                                     return x < c.first;
                                   });
                if (it != b.begin() && v[1 - d] <= std::prev(it)->second)
                  v[1 - d] = std::prev(it)->first;
              }
          if (result.empty() || v.distance(result.back()) > snap)
            result.push_back(v);
        }
      while (result.size() > 1 &&
             result.front().distance(result.back()) <= snap)
        result.pop_back();
      return result;
    }

    /**
     * The box as a polygon through its corners and every breakpoint, the
     * same ones on opposite sides: OpenCASCADE then splits both sides alike
     * even where a sliver of a polygon was left out on one side.
     */
    int
    add_box(
      const Point<2>                                              &box,
      const std::array<std::vector<std::pair<double, double>>, 2> &breakpoints)
    {
      namespace occ = gmsh::model::occ;
      std::vector<Point<2>> corners;
      const auto            along = [&](const unsigned int d, const double at) {
        std::vector<Point<2>> points;
        for (const auto &c : breakpoints[d])
          if (c.first > 0 && c.first < box[1 - d])
            {
              Point<2> x;
              x[d]     = at;
              x[1 - d] = c.first;
              points.push_back(x);
            }
        return points;
      };
      // Counterclockwise: bottom, right, top, left.
      std::vector<Point<2>> outline = {Point<2>(0, 0)};
      for (const auto &x : along(1, 0.))
        outline.push_back(x);
      outline.emplace_back(box[0], 0);
      for (const auto &x : along(0, box[0]))
        outline.push_back(x);
      outline.push_back(box);
      auto top = along(1, box[1]);
      for (auto x = top.rbegin(); x != top.rend(); ++x)
        outline.push_back(*x);
      outline.emplace_back(0, box[1]);
      auto left = along(0, 0.);
      for (auto x = left.rbegin(); x != left.rend(); ++x)
        outline.push_back(*x);
      std::vector<int> points, lines;
      for (const auto &v : outline)
        points.push_back(occ::addPoint(v[0], v[1], 0));
      for (unsigned int i = 0; i < points.size(); ++i)
        lines.push_back(
          occ::addLine(points[i], points[(i + 1) % points.size()]));
      return occ::addPlaneSurface({occ::addCurveLoop(lines)});
    }

    internal::GmshTriangles
    generate(const std::vector<std::pair<std::vector<Point<2>>, unsigned int>>
                            &polygons,
             const Point<2> &box,
             const double    size)
    {
      namespace occ     = gmsh::model::occ;
      const double snap = 1e-7 * std::max(box[0], box[1]);
      // Features this much smaller than an element are not meshed anyway.
      const double tolerance = std::max(snap, 1e-3 * size);
      gmsh::option::setNumber("Geometry.ToleranceBoolean", snap);
      std::vector<ConvexPolygon> clipped;
      for (const auto &polygon : polygons)
        clipped.push_back(clipped_to_box(polygon.first, box));
      const auto       breakpoints = side_breakpoints(clipped, box, tolerance);
      const int        rectangle   = add_box(box, breakpoints);
      gmsh::vectorpair tools;
      std::vector<unsigned int> tool_phase;
      for (unsigned int k = 0; k < clipped.size(); ++k)
        {
          const ConvexPolygon p =
            snapped_to_sides(clipped[k], box, breakpoints, snap, tolerance);
          // Slivers (also those flattened onto a side) are left out; the
          // box's own breakpoints keep the sides matched.
          if (p.size() < 3 || area(p) < snap * std::max(box[0], box[1]))
            continue;
          std::vector<int> points, lines;
          for (const auto &v : p)
            points.push_back(occ::addPoint(v[0], v[1], 0));
          for (unsigned int i = 0; i < points.size(); ++i)
            lines.push_back(
              occ::addLine(points[i], points[(i + 1) % points.size()]));
          tools.push_back(
            {2, occ::addPlaneSurface({occ::addCurveLoop(lines)})});
          tool_phase.push_back(polygons[k].second);
        }
      gmsh::vectorpair              pieces;
      std::vector<gmsh::vectorpair> children;
      occ::fragment({{2, rectangle}}, tools, pieces, children);
      occ::synchronize();

      // A piece of a polygon gets its phase + 1, the rest of the box 0.
      std::map<int, unsigned int> material;
      for (const auto &piece : pieces)
        material[piece.second] = 0;
      for (unsigned int t = 0; t < tools.size(); ++t)
        for (const auto &piece : children[t + 1])
          material[piece.second] = tool_phase[t] + 1;
      std::map<unsigned int, std::vector<int>> groups;
      for (const auto &[tag, id] : material)
        groups[id].push_back(tag);
      for (const auto &[id, tags] : groups)
        gmsh::model::addPhysicalGroup(2, tags, static_cast<int>(id) + 1);

      // Opposite sides: the same curves, shifted by the box.
      // OpenCASCADE pads bounding boxes (by at least 1e-7): search with
      // a margin well above that, compare relative to the box.
      const double scale = std::max(box[0], box[1]);
      const double eps   = std::max(1e-6, 1e-5 * scale);
      for (unsigned int d = 0; d < 2; ++d)
        {
          const auto low  = side_curves(d, 0, eps),
                     high = side_curves(d, box[d], eps);
          bool match      = !low.empty() && low.size() == high.size();
          for (unsigned int i = 0; match && i < low.size(); ++i)
            match =
              std::abs(low[i].first[0] - high[i].first[0]) < 1e-6 * scale &&
              std::abs(low[i].first[1] - high[i].first[1]) < 1e-6 * scale;
          AssertThrow(match,
                      ExcMessage(context +
                                 ": the structure is not periodic "
                                 "on the box: its sides x" +
                                 std::to_string(d) + " = 0 and x" +
                                 std::to_string(d) + " = " +
                                 std::to_string(box[d]) + " do not match"));
          std::vector<double> shift = {
            1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
          shift[4 * d + 3] = box[d];
          std::vector<int> slaves, masters;
          for (unsigned int i = 0; i < low.size(); ++i)
            {
              slaves.push_back(high[i].second);
              masters.push_back(low[i].second);
            }
          gmsh::model::mesh::setPeriodic(1, slaves, masters, shift);
        }

      return internal::gmsh_triangulate(size, context);
    }
  } // namespace



  void
  periodic_phase_mesh(
    const std::vector<std::pair<std::vector<Point<2>>, unsigned int>> &polygons,
    const Point<2>                                                    &box,
    const double                                                       size,
    Triangulation<2>                                                  &tria,
    const MPI_Comm                                                     comm)
  {
    AssertThrow(box[0] > 0 && box[1] > 0 && size > 0,
                ExcMessage(context + ": the box and the element size must "
                                     "be positive"));
    AssertThrow(size < std::min(box[0], box[1]),
                ExcMessage(context + ": the element size " +
                           std::to_string(size) +
                           " is not smaller than the box"));
    // Meshed once, on the root, so that every rank reads the same mesh.
    const internal::GmshTriangles mesh =
      internal::gmsh_on_root(comm, "forma-periodic-phase-mesh", context, [&]() {
        return generate(polygons, box, size);
      });
    Triangulation<2> read;
    read.create_triangulation(mesh.vertices, mesh.cells, SubCellData());
    for (const auto &cell : read.active_cell_iterators())
      cell->set_material_id(cell->material_id() -
                            1); // physical tags are id + 1
    check_mesh_validity(read, "the periodic phase mesh");
    tria.clear();
    tria.copy_triangulation(read);
  }
} // namespace forma
