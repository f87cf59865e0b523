// resample_boundaries() in 3D (mesh/boundary_resampling.h, CGAL isotropic
// remeshing) on the surfaces of a tetrahedral cube in two materials (x <
// 1/2: 0, else 1) whose top bulges and whose vertices crowd unevenly in x,
// with a sharp edge inside one patch that has a short segment; the bottom
// (id 4) is kept.
// Checks: every key (materials, boundary id, the interface) keeps its
// pieces; the short segment of the sharp edge goes; each material keeps its
// volume to round-off; new vertices lie on the old surface but for the volume
// correction; the kept bottom keeps its area and plane; the worst surface
// triangle gets better; a target size gives about the expected count; Gmsh
// meshes the result with its ids and volumes; a patch that is not a manifold
// surface is refused.

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <forma/mesh/boundary_resampling.h>

#include "../tests.h"

#include <set>

using namespace dealii;
using Boundaries = forma::RegionBoundaries<3>;
using Key        = std::array<unsigned int, 3>;

namespace
{
  const unsigned int none = numbers::invalid_material_id;

  Key
  key(const Boundaries::Facet &f)
  {
    return {{f.inside, f.outside, f.boundary_id}};
  }

  // The distorted two-material cube, meshed in tetrahedra.
  void
  make_cube(Triangulation<3> &tria)
  {
    Triangulation<3> hexes;
    GridGenerator::subdivided_hyper_cube(hexes, 4, 0, 1, true);
    GridGenerator::convert_hypercube_to_simplex_mesh(hexes, tria);
    for (const auto &cell : tria.active_cell_iterators())
      cell->set_material_id(cell->center()[0] > .5 ? 1 : 0);
    // The top (id 5) joins the front (y = 0, id 2): their common edge is
    // a sharp edge inside one patch; near it, the vertices of x = 1/4
    // crowd towards x = 1/2 (a segment of 0.05 on that edge).
    for (const auto &face : tria.active_face_iterators())
      if (face->at_boundary() && face->boundary_id() == 5)
        face->set_boundary_id(2);
    GridTools::transform(
      [](const Point<3> &p) {
        const double g = p[0] < .25 ?
                           1.8 * p[0] :
                           (p[0] < .5 ? .45 + .2 * (p[0] - .25) : p[0]);
        // Both maps of x increase: so does their mix.
        const double w = (1 - p[1]) * p[2];
        const double x =
          w * g + (1 - w) * (p[0] + .05 * (1 + p[1]) *
                                      std::sin(2 * numbers::PI * p[0]));
        return Point<3>(x,
                        p[1],
                        p[2] * (1 + .3 * std::sin(numbers::PI * x) *
                                      std::sin(numbers::PI * p[1])));
      },
      tria);
  }

  // Its boundary and interface facets, normals out of `inside`.
  Boundaries
  boundaries_of(const Triangulation<3> &tria)
  {
    Boundaries b;
    b.vertices = tria.get_vertices();
    for (const auto &cell : tria.active_cell_iterators())
      for (const auto f : cell->face_indices())
        {
          const auto         face    = cell->face(f);
          types::material_id outside = none;
          if (!face->at_boundary())
            {
              outside = cell->neighbor(f)->material_id();
              if (outside <= cell->material_id())
                continue;
            }
          Boundaries::Facet facet{{{face->vertex_index(0),
                                    face->vertex_index(1),
                                    face->vertex_index(2)}},
                                  cell->material_id(),
                                  outside,
                                  face->at_boundary() ? face->boundary_id() :
                                                        types::boundary_id(0)};
          const auto n = cross_product_3d(face->vertex(1) - face->vertex(0),
                                          face->vertex(2) - face->vertex(0));
          if (n * (cell->center() - face->vertex(0)) > 0)
            std::swap(facet.vertices[0], facet.vertices[1]);
          b.facets.push_back(facet);
        }
    return b;
  }

  std::array<Point<3>, 3>
  corners(const Boundaries &b, const Boundaries::Facet &f)
  {
    return {{b.vertices[f.vertices[0]],
             b.vertices[f.vertices[1]],
             b.vertices[f.vertices[2]]}};
  }

  // Twice the inradius over the circumradius: 1 for an equilateral
  // triangle, 0 for a degenerate one.
  double
  radius_ratio(const std::array<Point<3>, 3> &x)
  {
    const double a = (x[1] - x[0]).norm(), c = (x[2] - x[1]).norm(),
                 d    = (x[0] - x[2]).norm();
    const double area = cross_product_3d(x[1] - x[0], x[2] - x[0]).norm() / 2;
    return 16 * area * area / (a * c * d * (a + c + d));
  }

  double
  worst_free_triangle(const Boundaries &b)
  {
    double worst = 1;
    for (const auto &f : b.facets)
      if (f.boundary_id != 4 || f.outside != none)
        worst = std::min(worst, radius_ratio(corners(b, f)));
    return worst;
  }

  // Distance from x to the triangle (brute force by sampling would be
  // coarse: project on the plane, else to the nearest edge).
  double
  distance(const Point<3> &x, const std::array<Point<3>, 3> &t)
  {
    const auto   n  = cross_product_3d(t[1] - t[0], t[2] - t[0]);
    const double h  = (x - t[0]) * n / n.norm();
    const auto   p  = x - h * n / n.norm();
    bool         in = true;
    for (unsigned int k = 0; k < 3; ++k)
      in = in && cross_product_3d(t[(k + 1) % 3] - t[k], p - t[k]) * n >= 0;
    if (in)
      return std::abs(h);
    double best = std::numeric_limits<double>::max();
    for (unsigned int k = 0; k < 3; ++k)
      {
        const auto   e = t[(k + 1) % 3] - t[k];
        const double s = std::clamp((x - t[k]) * e / (e * e), 0., 1.);
        best           = std::min(best, (x - (t[k] + s * e)).norm());
      }
    return best;
  }

  double
  farthest_off(const Boundaries &old, const Boundaries &b)
  {
    double off = 0;
    for (const auto &f : b.facets)
      for (const auto v : f.vertices)
        {
          double d = std::numeric_limits<double>::max();
          for (const auto &g : old.facets)
            if (key(g) == key(f))
              d = std::min(d, distance(b.vertices[v], corners(old, g)));
          off = std::max(off, d);
        }
    return off;
  }

  // The shortest edge between two vertices of the front (y = 0) that
  // both lie on the top (above z = 0.99, the bulge is 0 there).
  double
  shortest_sharp(const Boundaries &b)
  {
    double shortest = 1;
    for (const auto &f : b.facets)
      for (unsigned int k = 0; k < 3; ++k)
        {
          const auto &x = b.vertices[f.vertices[k]],
                     &y = b.vertices[f.vertices[(k + 1) % 3]];
          if (std::abs(x[1]) < 1e-12 && std::abs(y[1]) < 1e-12 && x[2] > .99 &&
              y[2] > .99)
            shortest = std::min(shortest, (x - y).norm());
        }
    return shortest;
  }

  std::pair<double, double> // area, largest |z|
  bottom(const Boundaries &b)
  {
    double area = 0, z = 0;
    for (const auto &f : b.facets)
      if (f.boundary_id == 4 && f.outside == none)
        {
          const auto x = corners(b, f);
          area += cross_product_3d(x[1] - x[0], x[2] - x[0]).norm() / 2;
          for (const auto &p : x)
            z = std::max(z, std::abs(p[2]));
        }
    return {area, z};
  }
} // namespace

int
main()
{
  initlog();
  Triangulation<3> cube;
  make_cube(cube);
  const Boundaries          old = boundaries_of(cube);
  forma::BoundaryResampling o;
  o.kept_boundaries  = {4};
  const Boundaries b = forma::resample_boundaries(old, o);

  std::set<Key> keys_old, keys_new;
  for (const auto &f : old.facets)
    keys_old.insert(key(f));
  for (const auto &f : b.facets)
    keys_new.insert(key(f));
  check("every key keeps its pieces", keys_old == keys_new);
  const auto v0 = forma::region_volumes(old), v1 = forma::region_volumes(b);
  for (const auto &[m, v] : v0)
    deallog << "material " << m << ": volume " << rounded(v, 6)
            << ", relative change below 1e-12: "
            << (std::abs(v1.at(m) - v) < 1e-12 * v ? "yes" : "NO") << std::endl;
  // Off the old surface by the volume correction only: a fraction of the
  // sagitta of the bulge's facets (curvature 0.3 pi^2, 0.25 wide: 0.023).
  check("new vertices lie within 5e-3 of the old surface",
        farthest_off(old, b) < 5e-3);
  const auto [area0, z0] = bottom(old);
  const auto [area1, z1] = bottom(b);
  check("the kept bottom keeps its area and plane",
        std::abs(area1 - area0) < 1e-12 && z0 == 0 && z1 == 0);
  deallog << "shortest edge on the sharp edge y = 0, z = top: "
          << rounded(shortest_sharp(old), 2)
          << " -> above 0.1: " << (shortest_sharp(b) > .1 ? "yes" : "NO")
          << std::endl;
  const double q0 = worst_free_triangle(old), q1 = worst_free_triangle(b);
  // Beside the feature curves, which stay, CGAL cannot mend every triangle.
  deallog << "worst free triangle (radius ratio) " << rounded(q0, 2)
          << " -> at least twice that: " << (q1 > 2 * q0 ? "yes" : "NO")
          << std::endl;

  o.size                = .1;
  const Boundaries c    = forma::resample_boundaries(old, o);
  double           area = 0;
  for (const auto &f : c.facets)
    {
      const auto x = corners(c, f);
      area += cross_product_3d(x[1] - x[0], x[2] - x[0]).norm() / 2;
    }
  // An equilateral triangle of side 0.1 covers 4.3e-3.
  const double expected = area / (std::sqrt(3.) / 4 * .01);
  deallog << "size 0.1: " << old.facets.size() << " -> about the expected "
          << "count (within 40%): "
          << (std::abs(c.facets.size() - expected) < .4 * expected ? "yes" :
                                                                     "NO")
          << std::endl;

  Triangulation<3> tria;
  forma::read_regions_mesh(forma::mesh_regions(b, false), tria);
  std::set<types::boundary_id> ids;
  for (const auto &face : tria.active_face_iterators())
    if (face->at_boundary())
      ids.insert(face->boundary_id());
  std::map<types::material_id, double> volume;
  for (const auto &cell : tria.active_cell_iterators())
    volume[cell->material_id()] += cell->measure();
  deallog << "Gmsh mesh of the result: boundary ids";
  for (const auto id : ids)
    deallog << " " << id;
  deallog << "; its volumes are the surfaces': "
          << (std::abs(volume[0] - v1.at(0)) < 1e-10 &&
                  std::abs(volume[1] - v1.at(1)) < 1e-10 ?
                "yes" :
                "NO")
          << std::endl;

  // Two tetrahedra of one body sharing an edge: one patch through that
  // edge, which four facets meet.
  Boundaries bowtie;
  bowtie.vertices = {Point<3>(0, 0, 0),
                     Point<3>(0, 0, 1),
                     Point<3>(1, 0, 0),
                     Point<3>(0, 1, 0),
                     Point<3>(-1, 0, 0),
                     Point<3>(0, -1, 0)};
  for (const auto &t : std::vector<std::array<unsigned int, 3>>{{0, 3, 2},
                                                                {0, 2, 1},
                                                                {0, 1, 3},
                                                                {1, 2, 3},
                                                                {0, 5, 4},
                                                                {0, 4, 1},
                                                                {0, 1, 5},
                                                                {1, 4, 5}})
    bowtie.facets.push_back({t, 0, none, 0});
  expect_refusal(
    "a surface that is not a manifold",
    [&] { forma::resample_boundaries(bowtie, forma::BoundaryResampling()); },
    "is not a manifold");
}
