// resample_boundaries() (mesh/boundary_resampling.h) on three regions made
// by hand: a half disk (material 0) whose arc is sampled very unevenly, glued
// to a rectangle (material 1) by a conforming interface, and a square
// (material 2) cut from the rectangle's right side (two coincident sides,
// id 10). The rectangle's bottom (id 1) is kept.
// Checks: every key (materials, boundary id) keeps its pieces; new vertices
// lie on the old polylines but for the area correction; corners and kept facets
// stay; areas change by less than 1e-3; the cut sides stay coincident (also
// when one side's part is fixed: its twin stays too); the
// spacing evens out; a target size gives the expected count; Gmsh meshes the
// result with its ids; a resampling whose curves would cross is refused.

#include <deal.II/grid/tria.h>

#include <forma/mesh/boundary_resampling.h>

#include "../tests.h"

#include <algorithm>
#include <map>
#include <set>

using namespace dealii;
using Boundaries = forma::RegionBoundaries<2>;
using Key        = std::array<unsigned int, 3>;

namespace
{
  const unsigned int none = numbers::invalid_material_id;

  struct Builder
  {
    Boundaries                                          b;
    std::map<std::tuple<int, double, double>, unsigned> index;

    // Vertex at p; `layer` 1 makes the cut side's own copies.
    unsigned int
    vertex(const Point<2> &p, const int layer)
    {
      const auto [it, added] =
        index.emplace(std::make_tuple(layer, p[0], p[1]), b.vertices.size());
      if (added)
        b.vertices.push_back(p);
      return it->second;
    }

    void
    chain(const std::vector<Point<2>> &p,
          const unsigned int           inside,
          const unsigned int           outside,
          const unsigned int           id,
          const int                    layer = 0)
    {
      for (unsigned int i = 0; i + 1 < p.size(); ++i)
        b.facets.push_back({{{vertex(p[i], layer), vertex(p[i + 1], layer)}},
                            inside,
                            outside,
                            id});
    }
  };

  std::vector<Point<2>>
  line(const Point<2> &a, const Point<2> &c, const std::vector<double> &t)
  {
    std::vector<Point<2>> p;
    for (const double s : t)
      p.push_back(a + s * (c - a));
    return p;
  }

  // 0, ..., 1 in n steps alternately short and long (1 : 4), as a shape
  // optimization leaves them where it stretched the boundary.
  std::vector<double>
  uneven(const unsigned int n)
  {
    std::vector<double> t{0};
    for (unsigned int k = 0; k < n; ++k)
      t.push_back(t.back() + (k % 2 ? 4 : 1));
    for (auto &x : t)
      x /= t.back();
    return t;
  }

  std::vector<double>
  reversed(std::vector<double> t)
  {
    std::reverse(t.begin(), t.end());
    for (auto &x : t)
      x = 1 - x;
    return t;
  }

  Boundaries
  three_regions()
  {
    Builder               r;
    std::vector<Point<2>> arc;
    for (const double t : uneven(40))
      arc.emplace_back(t < 1 ? std::cos(numbers::PI * t) : -1.,
                       t < 1 ? std::sin(numbers::PI * t) : 0.);
    r.chain(arc, 0, none, 2);
    r.chain(line({-1, 0}, {1, 0}, {0, .25, .5, .75, 1}), 0, 1, 0);
    r.chain(line({-1, -.5}, {1, -.5}, {0, .5, 1}), 1, none, 1);
    r.chain(line({1, -.5}, {1, 0}, uneven(8)), 1, none, 10);
    r.chain(line({-1, 0}, {-1, -.5}, {0, 1}), 1, none, 3);
    r.chain(line({1, 0}, {1, -.5}, reversed(uneven(8))), 2, none, 10, 1);
    r.chain(line({1, -.5}, {1.5, -.5}, {0, 1}), 2, none, 4, 1);
    r.chain(line({1.5, -.5}, {1.5, 0}, {0, 1}), 2, none, 4, 1);
    r.chain(line({1.5, 0}, {1, 0}, {0, 1}), 2, none, 4, 1);
    return r.b;
  }

  Key
  key(const Boundaries::Facet &f)
  {
    return {{f.inside, f.outside, f.boundary_id}};
  }

  double
  distance_to(const Boundaries &b, const Key &k, const Point<2> &x)
  {
    double d = 1e300;
    for (const auto &f : b.facets)
      if (key(f) == k)
        {
          const auto        &a = b.vertices[f.vertices[0]];
          const Tensor<1, 2> e = b.vertices[f.vertices[1]] - a;
          const double       s = std::clamp((x - a) * e / (e * e), 0., 1.);
          d                    = std::min(d, x.distance(a + s * e));
        }
    return d;
  }

  // Segment lengths of the facets of key k, smallest and largest.
  std::pair<double, double>
  spacing(const Boundaries &b, const Key &k, unsigned int &count)
  {
    double lo = 1e300, hi = 0;
    count = 0;
    for (const auto &f : b.facets)
      if (key(f) == k)
        {
          const double l =
            b.vertices[f.vertices[0]].distance(b.vertices[f.vertices[1]]);
          lo = std::min(lo, l), hi = std::max(hi, l), ++count;
        }
    return {lo, hi};
  }

  std::set<std::pair<double, double>>
  points_of(const Boundaries &b, const Key &k)
  {
    std::set<std::pair<double, double>> s;
    for (const auto &f : b.facets)
      if (key(f) == k)
        for (const auto v : f.vertices)
          s.emplace(b.vertices[v][0], b.vertices[v][1]);
    return s;
  }
} // namespace

int
main()
{
  initlog();
  const Boundaries          old = three_regions();
  forma::BoundaryResampling o;
  o.kept_boundaries  = {1};
  const Boundaries b = forma::resample_boundaries(old, o);

  std::set<Key> keys_old, keys_new;
  for (const auto &f : old.facets)
    keys_old.insert(key(f));
  for (const auto &f : b.facets)
    keys_new.insert(key(f));
  check("every key keeps its pieces", keys_old == keys_new);
  double off = 0;
  for (const auto &f : b.facets)
    for (const auto v : f.vertices)
      off = std::max(off, distance_to(old, key(f), b.vertices[v]));
  // Off the old polyline by a fraction of the sagitta of the arc's coarsest
  // segments (0.157^2 / 8 = 3e-3), which gives back the corners' areas.
  check("new vertices lie within 1e-3 of the old boundary", off < 1e-3);
  const Key bottom{{1, none, 1}};
  check("kept facets stay", points_of(b, bottom) == points_of(old, bottom));
  bool corners = true;
  for (const Point<2> c :
       {Point<2>(-1, -.5), Point<2>(1, -.5), Point<2>(1.5, 0)})
    corners = corners &&
              points_of(b, {{c[0] > 1.2 ? 2u : 1u, none, c[0] > 1.2 ? 4u : 1u}})
                .count({c[0], c[1]});
  check("corners stay", corners);
  const auto a0 = forma::region_areas(old), a1 = forma::region_areas(b);
  for (const auto &[m, a] : a0)
    deallog << "material " << m << ": area " << rounded(a, 6)
            << ", relative change below 1e-3: "
            << (std::abs(a1.at(m) - a) < 1e-3 * a ? "yes" : "NO") << std::endl;
  check("the two sides of the cut stay coincident",
        points_of(b, {{1, none, 10}}) == points_of(b, {{2, none, 10}}));

  unsigned int n_old, n_new;
  const Key    arc{{0, none, 2}};
  const auto   s_old = spacing(old, arc, n_old);
  const auto   s_new = spacing(b, arc, n_new);
  deallog << "arc: " << n_old << " -> " << n_new
          << " segments, largest / smallest "
          << rounded(s_old.second / s_old.first, 3) << " -> below 1.5: "
          << (s_new.second / s_new.first < 1.5 ? "yes" : "NO") << std::endl;
  {
    // Material 1 fixed: its side of the cut stays, and so does material
    // 2's side, which must stay coincident with it.
    forma::BoundaryResampling fixed;
    fixed.kept_materials = {1};
    const Boundaries k   = forma::resample_boundaries(old, fixed);
    check("a fixed part's cut side and its twin stay",
          points_of(k, {{1, none, 10}}) == points_of(old, {{1, none, 10}}) &&
            points_of(k, {{2, none, 10}}) == points_of(old, {{2, none, 10}}));
  }
  o.size             = 0.1;
  const Boundaries c = forma::resample_boundaries(old, o);
  spacing(c, arc, n_new);
  deallog << "size 0.1: arc of length pi in " << n_new << " segments"
          << std::endl;

  Triangulation<2> tria;
  forma::read_regions_mesh(forma::mesh_regions(b, false), tria);
  std::map<unsigned int, unsigned int> faces;
  for (const auto &face : tria.active_face_iterators())
    if (face->at_boundary())
      ++faces[face->boundary_id()];
  deallog << "Gmsh mesh of the result: boundary ids";
  for (const auto &[id, n] : faces)
    deallog << " " << id;
  deallog << "; kept bottom faces " << faces[1] << std::endl;

  // A V notch in a straight side (turns below the feature angle) with the
  // tip of another part in it: resampled with a long size and no limit on
  // the turns (which would keep the notch), the side straightens through
  // the tip.
  Builder t;
  t.chain(
    {{0, 0}, {0, -1}, {4, -1}, {4, 0}, {3.4, 0}, {3, -.1}, {2.6, 0}, {0, 0}},
    0,
    none,
    0);
  t.chain({{3, -.05}, {3.1, .1}, {2.9, .1}, {3, -.05}}, 1, none, 0);
  forma::BoundaryResampling coarse;
  coarse.size     = 4;
  coarse.max_turn = 10;
  expect_refusal(
    "a resampling that cuts through another part",
    [&] { forma::resample_boundaries(t.b, coarse); },
    "boundary resampling: the resampled boundaries cross");
}
