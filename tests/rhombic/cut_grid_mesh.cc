// The cut-regular-grid mesh of the thesis's ch. 4.8 baseline: a polygon
// with a hole, given as shuffled sides of mixed orientation, cut by a
// square grid. Checked against independent computations: each material
// id's area equals the area of its square clipped to the polygon
// (Sutherland-Hodgman, less the hole's clip), the boundary ids' lengths
// equal the polygon's, and the domain's inside test and signed distance
// agree with the geometry.

#include <deal.II/base/mpi.h>
#include <deal.II/grid/tria.h>

#include <forma/mesh/cut_grid_mesh.h>
#include <forma/mesh/polygon_domain.h>

#include "../tests.h"

#include <algorithm>
#include <cmath>
#include <map>

using namespace dealii;
using forma::PolygonDomain;

namespace
{
  using Polygon = std::vector<Point<2>>;

  double
  area(const Polygon &p)
  {
    double a = 0;
    for (unsigned int k = 0; k < p.size(); ++k)
      {
        const Point<2> &u = p[k], &v = p[(k + 1) % p.size()];
        a += 0.5 * (u[0] * v[1] - u[1] * v[0]);
      }
    return a;
  }

  // The part of p with x[d] * sign <= value * sign.
  Polygon
  clip(const Polygon     &p,
       const unsigned int d,
       const double       value,
       const int          sign)
  {
    Polygon    out;
    const auto in = [&](const Point<2> &x) {
      return sign * (x[d] - value) <= 0;
    };
    for (unsigned int k = 0; k < p.size(); ++k)
      {
        const Point<2> &a = p[k], &b = p[(k + 1) % p.size()];
        if (in(a))
          out.push_back(a);
        if (in(a) != in(b))
          {
            const double t = (value - a[d]) / (b[d] - a[d]);
            out.push_back(a + t * (b - a));
          }
      }
    return out;
  }

  double
  clipped_area(Polygon p, const Point<2> &o, const double h)
  {
    p = clip(p, 0, o[0], -1);
    p = clip(p, 0, o[0] + h, 1);
    p = clip(p, 1, o[1], -1);
    p = clip(p, 1, o[1] + h, 1);
    return p.size() < 3 ? 0. : std::abs(area(p));
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  // A 24-gon of radius 1 (upper half id 1, lower half id 2) with a
  // rectangular hole (id 3).
  Polygon        outer, hole = {Point<2>(-0.3, -0.25),
                                Point<2>(0.2, -0.25),
                                Point<2>(0.2, 0.15),
                                Point<2>(-0.3, 0.15)};
  const Point<2> center(0.03, -0.02);
  for (unsigned int k = 0; k < 24; ++k)
    outer.push_back(center + Point<2>(std::cos(2 * M_PI * k / 24),
                                      std::sin(2 * M_PI * k / 24)));
  std::vector<PolygonDomain::Segment> sides;
  double                              length[4] = {0, 0, 0, 0};
  for (unsigned int k = 0; k < 24; ++k)
    {
      const auto     id = static_cast<types::boundary_id>(k < 12 ? 1 : 2);
      const Point<2> a = outer[k], b = outer[(k + 1) % 24];
      sides.push_back(k % 3 ? PolygonDomain::Segment{a, b, id} :
                              PolygonDomain::Segment{b, a, id});
      length[id] += a.distance(b);
    }
  for (unsigned int k = 0; k < 4; ++k)
    {
      sides.push_back({hole[k], hole[(k + 1) % 4], 3});
      length[3] += hole[k].distance(hole[(k + 1) % 4]);
    }
  std::reverse(sides.begin(), sides.end());
  std::swap(sides[3], sides[17]);
  const PolygonDomain domain(sides);

  deallog << "loops " << domain.loops.size() << ", holes "
          << std::count_if(domain.loops.begin(),
                           domain.loops.end(),
                           [](const auto &l) { return l.hole; })
          << std::endl;
  deallog << "inside: ring " << domain.inside(Point<2>(0.6, 0.0)) << ", hole "
          << domain.inside(Point<2>(0.0, 0.0)) << ", outside "
          << domain.inside(Point<2>(1.2, 0.0)) << std::endl;
  // The hole's center is 0.2 from its nearest sides (y = -0.25, 0.15).
  deallog << "signed distance at the hole's center "
          << domain.signed_distance(Point<2>(-0.05, -0.05)) << std::endl;
  for (types::boundary_id id = 1; id <= 3; ++id)
    deallog << "length of id " << id << ": |domain - exact| "
            << (std::abs(domain.length(id) - length[id]) < 1e-12 ? "< 1e-12" :
                                                                   "LARGE")
            << std::endl;

  // Points just inside next to boundary points, corners included (convex
  // corners of the 24-gon, reflex corners of the material at the hole).
  {
    unsigned int inside = 0, near = 0, n = 0;
    for (const Polygon *p : {&outer, &hole})
      for (unsigned int k = 0; k < p->size(); ++k)
        for (const double t : {0., 0.3})
          {
            const Point<2> x =
              (*p)[k] + t * ((*p)[(k + 1) % p->size()] - (*p)[k]);
            const Point<2> y = domain.point_inside_near(x, 1e-4);
            inside += domain.inside(y);
            near += x.distance(y) < 3e-4;
            ++n;
          }
    deallog << "points inside near the boundary: " << inside << " of " << n
            << " inside, " << near << " within 3 depths" << std::endl;
  }

  const double          h = 0.3;
  const Point<2>        origin(-1.2, -1.1);
  Triangulation<2>      tria;
  std::vector<Point<2>> squares;
  forma::cut_grid_mesh(domain, origin, h, 0.5 * h, tria, squares);

  std::map<types::material_id, double> mesh_area;
  double                               boundary[4] = {0, 0, 0, 0};
  double                               smallest    = 1e300;
  for (const auto &cell : tria.active_cell_iterators())
    {
      mesh_area[cell->material_id()] += cell->measure();
      smallest = std::min(smallest, cell->measure());
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          boundary[cell->face(f)->boundary_id()] += cell->face(f)->measure();
    }
  unsigned int expected = 0;
  for (int i = -1; i < 10; ++i)
    for (int j = -1; j < 10; ++j)
      expected += clipped_area(outer, origin + Point<2>(i * h, j * h), h) -
                    clipped_area(hole, origin + Point<2>(i * h, j * h), h) >
                  1e-12;
  double error = 0, total = 0;
  for (unsigned int k = 0; k < squares.size(); ++k)
    {
      const double exact =
        clipped_area(outer, squares[k], h) - clipped_area(hole, squares[k], h);
      error = std::max(error, std::abs(mesh_area[k] - exact));
      total += mesh_area[k];
    }
  deallog << "squares " << squares.size() << " (expected " << expected
          << "), material ids " << mesh_area.size() << ", smallest cell "
          << (smallest > 0 ? "positive" : "NOT POSITIVE") << std::endl;
  deallog << "area per square: max |mesh - clipped| "
          << (error < 1e-10 ? "< 1e-10" : std::to_string(error)) << std::endl;
  deallog << "total area " << total << " (exact "
          << std::abs(area(outer)) - std::abs(area(hole)) << ")" << std::endl;
  for (types::boundary_id id = 1; id <= 3; ++id)
    deallog << "boundary id " << id << ": length on the mesh - exact "
            << (std::abs(boundary[id] - length[id]) < 1e-10 ? "< 1e-10" :
                                                              "LARGE")
            << std::endl;
}
