// The crossing tests of IPC's initial-state check are exact (CGAL's
// filtered predicates). On flat faces turned and tilted, with coordinates
// rounded to 12 digits as a mesh file stores them, no edge crosses a
// triangle it does not touch. An edge and a triangle of one face of a
// cube of the 3D pile scene (parameter_files/transient_ipc/meshes/
// pile_3d.msh) are taken for crossing by the floating-point version of the
// test (kept here for comparison), which made IPC refuse the scene as
// "already intersecting"; the exact test does not. Proper crossings are
// still found; touching and collinear configurations are not crossings.

#include <forma/ipc/exact_predicates.h>

#include "../tests.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

using forma::ipc::Vec;

namespace
{
  Vec
  v(const double x, const double y, const double z = 0)
  {
    Vec p;
    p[0] = x, p[1] = y, p[2] = z;
    return p;
  }

  // The signs of floating-point volumes, as the test was before.
  bool
  float_crosses(const Vec &p,
                const Vec &q,
                const Vec &a,
                const Vec &b,
                const Vec &c)
  {
    const auto vol =
      [](const Vec &w, const Vec &x, const Vec &y, const Vec &z) {
        return dealii::cross_product_3d(x - w, y - w) * (z - w);
      };
    if (vol(a, b, c, p) * vol(a, b, c, q) >= 0)
      return false;
    const double s1 = vol(p, q, a, b), s2 = vol(p, q, b, c),
                 s3 = vol(p, q, c, a);
    return (s1 > 0 && s2 > 0 && s3 > 0) || (s1 < 0 && s2 < 0 && s3 < 0);
  }

  // A point of the face z = 0 of [0, 1]^2, turned about z and tilted about
  // x, rounded to 12 significant digits.
  Vec
  turned(const double x, const double y, const double angle, const double tilt)
  {
    const double X    = std::cos(angle) * x - std::sin(angle) * y,
                 Y    = std::sin(angle) * x + std::cos(angle) * y;
    const double p[3] = {X, std::cos(tilt) * Y, std::sin(tilt) * Y};
    Vec          r;
    for (unsigned int d = 0; d < 3; ++d)
      {
        char text[64];
        std::snprintf(text, sizeof(text), "%.12g", p[d] + 0.7);
        r[d] = std::atof(text);
      }
    return r;
  }
} // namespace

int
main()
{
  initlog();
  // A 4 x 4 grid of vertices on the face, its 18 triangles, the edges.
  unsigned int n_exact = 0, n_pairs = 0;
  for (unsigned int trial = 0; trial < 20; ++trial)
    {
      const double       angle = 0.1 + 0.05 * trial, tilt = 0.5 - 0.045 * trial;
      std::vector<Vec>   x;
      const unsigned int m = 4;
      for (unsigned int j = 0; j < m; ++j)
        for (unsigned int i = 0; i < m; ++i)
          x.push_back(turned(i / 3., j / 3., angle, tilt));
      std::vector<std::array<unsigned int, 3>> triangles;
      std::vector<std::array<unsigned int, 2>> edges;
      for (unsigned int j = 0; j + 1 < m; ++j)
        for (unsigned int i = 0; i + 1 < m; ++i)
          {
            const unsigned int a = j * m + i, b = a + 1, c = a + m + 1,
                               d = a + m;
            triangles.push_back({{a, b, c}});
            triangles.push_back({{a, c, d}});
            edges.push_back({{a, b}});
            edges.push_back({{a, d}});
            edges.push_back({{a, c}});
          }
      for (const auto &e : edges)
        for (const auto &t : triangles)
          {
            if (std::count(t.begin(), t.end(), e[0]) ||
                std::count(t.begin(), t.end(), e[1]))
              continue;
            ++n_pairs;
            n_exact += forma::ipc::segment_crosses_triangle(
              x[e[0]], x[e[1]], x[t[0]], x[t[1]], x[t[2]]);
          }
    }
  dealii::deallog << "coplanar edge-triangle pairs on turned faces: " << n_pairs
                  << std::endl;
  check("exact: none crosses", n_exact == 0);

  // The pile's face: an edge and a triangle of its quads, apart in the
  // face's plane.
  const Vec p = v(0.660549063482, 0.925761286901, 0.668005915284),
            q = v(0.660549063482, 0.865901782775, 0.910733828318),
            r = v(0.734023048126, 0.445575460919, 0.549586549864),
            s = v(0.697286055804, 0.68566837391, 0.608796232574),
            t = v(0.697286055804, 0.625808869784, 0.851524145608);
  check("pile face: floating point takes them for crossing",
        float_crosses(p, q, r, s, t));
  check("pile face: exact does not",
        !forma::ipc::segment_crosses_triangle(p, q, r, s, t));

  // Proper crossings and near misses.
  const Vec a = v(0, 0, 0), b = v(1, 0, 0), c = v(0, 1, 0);
  check("a segment through the triangle crosses",
        forma::ipc::segment_crosses_triangle(
          v(0.2, 0.2, -1), v(0.2, 0.2, 1), a, b, c));
  check("one beside it does not",
        !forma::ipc::segment_crosses_triangle(
          v(0.6, 0.6, -1), v(0.6, 0.6, 1), a, b, c));
  check("one ending on it does not (touching)",
        !forma::ipc::segment_crosses_triangle(
          v(0.2, 0.2, 0), v(0.2, 0.2, 1), a, b, c));
  check("one through its edge does not (touching)",
        !forma::ipc::segment_crosses_triangle(
          v(0.5, 0, -1), v(0.5, 0, 1), a, b, c));
  check("2D: crossing segments cross",
        forma::ipc::segments_cross_2d(v(0, 0), v(1, 1), v(0, 1), v(1, 0)));
  check("2D: collinear overlapping ones do not",
        !forma::ipc::segments_cross_2d(v(0, 0), v(2, 2), v(1, 1), v(3, 3)));
  check("2D: a T-junction does not",
        !forma::ipc::segments_cross_2d(v(0, 0), v(2, 0), v(1, 0), v(1, 1)));
}
