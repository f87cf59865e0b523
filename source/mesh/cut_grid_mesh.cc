#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/grid/tria.h>

#include <forma/base/application.h>
#include <forma/mesh/cut_grid_mesh.h>
#include <forma/mesh/mesh.h>
#include <forma/mesh/polygon_domain.h>

#include "gmsh_session.h"
#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

namespace forma
{
  using namespace dealii;

  namespace
  {
    const std::string context = "cut grid mesh";

    internal::GmshTriangles
    generate(const PolygonDomain   &domain,
             const Point<2>        &origin,
             const double           h,
             const double           size,
             std::vector<Point<2>> &squares)
    {
      namespace occ = gmsh::model::occ;
      const double scale =
        std::max(domain.hi[0] - domain.lo[0], domain.hi[1] - domain.lo[1]);
      gmsh::option::setNumber("Geometry.ToleranceBoolean", 1e-7 * scale);

      // The domain: its outer loops less its holes.
      gmsh::vectorpair outer, holes;
      for (const auto &loop : domain.loops)
        {
          std::vector<int> points, lines;
          for (const Point<2> &v : loop.vertices)
            points.push_back(occ::addPoint(v[0], v[1], 0));
          for (unsigned int i = 0; i < points.size(); ++i)
            lines.push_back(
              occ::addLine(points[i], points[(i + 1) % points.size()]));
          const int surface = occ::addPlaneSurface({occ::addCurveLoop(lines)});
          (loop.hole ? holes : outer).push_back({2, surface});
        }
      gmsh::vectorpair              body = outer;
      std::vector<gmsh::vectorpair> map;
      if (!holes.empty())
        occ::cut(outer, holes, body, map);

      // The grid squares over the domain's bounding box.
      const auto index = [&](const unsigned int d, const double x) {
        return static_cast<int>(std::floor((x - origin[d]) / h));
      };
      gmsh::vectorpair grid;
      for (int j = index(1, domain.lo[1]); j <= index(1, domain.hi[1]); ++j)
        for (int i = index(0, domain.lo[0]); i <= index(0, domain.hi[0]); ++i)
          grid.push_back(
            {2,
             occ::addRectangle(origin[0] + i * h, origin[1] + j * h, 0, h, h)});
      gmsh::vectorpair              pieces;
      std::vector<gmsh::vectorpair> children;
      occ::fragment(body, grid, pieces, children);
      // Keep the domain's pieces, drop the squares' parts outside it.
      std::set<int> kept;
      for (unsigned int k = 0; k < body.size(); ++k)
        for (const auto &piece : children[k])
          kept.insert(piece.second);
      gmsh::vectorpair outside;
      for (const auto &piece : pieces)
        if (piece.first == 2 && !kept.count(piece.second))
          outside.push_back(piece);
      occ::remove(outside, /*recursive=*/true);
      occ::synchronize();

      // Each piece lies in one square: the one holding its centroid.
      std::map<std::pair<int, int>, std::vector<int>> by_square;
      for (const int tag : kept)
        {
          double x, y, z;
          occ::getCenterOfMass(2, tag, x, y, z);
          by_square[{index(1, y), index(0, x)}].push_back(tag);
        }
      squares.clear();
      for (const auto &[ji, tags] : by_square)
        {
          squares.emplace_back(origin[0] + ji.second * h,
                               origin[1] + ji.first * h);
          gmsh::model::addPhysicalGroup(2, tags, squares.size());
        }

      return internal::gmsh_triangulate(size, context);
    }
  } // namespace



  void
  cut_grid_mesh(const PolygonDomain   &domain,
                const Point<2>        &origin,
                const double           spacing,
                const double           size,
                Triangulation<2>      &tria,
                std::vector<Point<2>> &squares,
                const MPI_Comm         comm)
  {
    AssertThrow(spacing > 0 && size > 0 && size <= spacing,
                ExcMessage(context + ": the grid spacing must be positive "
                                     "and the element size no larger"));
    const internal::GmshTriangles mesh =
      internal::gmsh_on_root(comm, "forma-cut-grid-mesh", context, [&]() {
        return generate(domain, origin, spacing, size, squares);
      });
    std::vector<double> corners;
    for (const Point<2> &p : squares)
      corners.insert(corners.end(), {p[0], p[1]});
    corners = Utilities::MPI::broadcast(comm, corners);
    squares.clear();
    for (unsigned int k = 0; k + 1 < corners.size(); k += 2)
      squares.emplace_back(corners[k], corners[k + 1]);
    // OpenCASCADE may move the outline by its boolean tolerance.
    const double tolerance =
      std::max(1e-6 * spacing,
               1e-5 * std::max(domain.hi[0] - domain.lo[0],
                               domain.hi[1] - domain.lo[1]));
    Triangulation<2> read;
    read.create_triangulation(mesh.vertices, mesh.cells, SubCellData());
    for (const auto &cell : read.active_cell_iterators())
      {
        cell->set_material_id(cell->material_id() - 1); // tags are k + 1
        for (const unsigned int f : cell->face_indices())
          if (cell->face(f)->at_boundary())
            {
              const auto id = domain.boundary_id(cell->face(f)->center(),
                                                 tolerance,
                                                 numbers::invalid_boundary_id);
              AssertThrow(id != numbers::invalid_boundary_id,
                          ExcMessage(
                            context + ": a boundary face at (" +
                            std::to_string(cell->face(f)->center()[0]) + ", " +
                            std::to_string(cell->face(f)->center()[1]) +
                            ") lies on no side of the domain"));
              cell->face(f)->set_boundary_id(id);
            }
      }
    // Material id k is square k: every square has cells (callers index
    // per-square data by material id).
    std::set<types::material_id> ids;
    for (const auto &cell : read.active_cell_iterators())
      ids.insert(cell->material_id());
    AssertThrow(ids.size() == squares.size() &&
                  *ids.rbegin() + 1 == squares.size(),
                ExcMessage(context +
                           ": the material ids are not the "
                           "squares 0.." +
                           std::to_string(squares.size() - 1)));
    check_mesh_validity(read, "the cut grid mesh");
    tria.clear();
    tria.copy_triangulation(read);
  }
} // namespace forma
