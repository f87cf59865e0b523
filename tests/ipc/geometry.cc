// The geometric core of IPC contact: distance formulas (gradients and
// Hessians against central differences, classification against dense
// sampling), barrier and mollifiers (values at the branch points,
// derivatives), additive CCD (never later than the true time of impact, on
// constructed cases including grazing and parallel motions and on random
// 2D trajectories with exact impact times) and the sort-and-sweep broad
// phase (the same pairs as brute force).

#include <deal.II/lac/full_matrix.h>

#include <forma/ipc/barrier.h>
#include <forma/ipc/broad_phase.h>
#include <forma/ipc/ccd.h>
#include <forma/ipc/distance.h>

#include "../tests.h"

#include <random>
#include <set>

using namespace forma::ipc;
using dealii::deallog;

std::mt19937 rng(7);

double
uniform(double a, double b)
{
  return std::uniform_real_distribution<double>(a, b)(rng);
}

Vec
random_vec(const unsigned int dim)
{
  Vec x;
  for (unsigned int d = 0; d < dim; ++d)
    x[d] = uniform(-1, 1);
  return x;
}

/// Largest relative error of the AD gradient and Hessian of a formula
/// against central differences.
void
check_derivatives(const DistanceType type, const char *name)
{
  double worst_g = 0, worst_h = 0;
  for (unsigned int trial = 0; trial < 20; ++trial)
    {
      std::vector<Vec> x(n_arguments(type));
      for (auto &v : x)
        v = random_vec(3);
      if (type == DistanceType::point_plane)
        x[2] /= x[2].norm();
      std::vector<double>        g;
      dealii::FullMatrix<double> H;
      distance_squared(type, x, &g, &H);
      const double h = 1e-6;
      for (unsigned int i = 0; i < g.size(); ++i)
        {
          if (type == DistanceType::point_plane && i >= 6)
            continue; // the normal is a constant of the plane
          auto xp = x, xm = x;
          xp[i / 3][i % 3] += h;
          xm[i / 3][i % 3] -= h;
          std::vector<double> gp, gm;
          const double        fd = (distance_squared(type, xp, &gp) -
                             distance_squared(type, xm, &gm)) /
                            (2 * h);
          worst_g =
            std::max(worst_g, std::abs(fd - g[i]) / (std::abs(g[i]) + 1e-3));
          for (unsigned int j = 0; j < g.size(); ++j)
            {
              const double fdh = (gp[j] - gm[j]) / (2 * h);
              worst_h =
                std::max(worst_h,
                         std::abs(fdh - H(j, i)) / (std::abs(H(j, i)) + 1e-2));
            }
        }
    }
  deallog << name << ": gradient vs differences "
          << (worst_g < 1e-6 ? "ok" : "FAILED") << ", Hessian vs differences "
          << (worst_h < 1e-5 ? "ok" : "FAILED") << std::endl;
}

double
sampled_distance(const std::vector<Vec> &a, const std::vector<Vec> &b)
{
  // Dense samples of two primitives (points, segments or triangles).
  const auto samples = [](const std::vector<Vec> &p) {
    std::vector<Vec>   s;
    const unsigned int n = 60;
    if (p.size() == 1)
      s.push_back(p[0]);
    else if (p.size() == 2)
      for (unsigned int i = 0; i <= n; ++i)
        s.push_back(p[0] + double(i) / n * (p[1] - p[0]));
    else
      for (unsigned int i = 0; i <= n; ++i)
        for (unsigned int j = 0; i + j <= n; ++j)
          s.push_back(p[0] + double(i) / n * (p[1] - p[0]) +
                      double(j) / n * (p[2] - p[0]));
    return s;
  };
  double d = 1e300;
  for (const Vec &x : samples(a))
    for (const Vec &y : samples(b))
      d = std::min(d, (x - y).norm());
  return d;
}

int
main()
{
  initlog();

  // Distance formulas.
  check_derivatives(DistanceType::point_point, "point-point");
  check_derivatives(DistanceType::point_edge, "point-edge");
  check_derivatives(DistanceType::point_triangle, "point-triangle");
  check_derivatives(DistanceType::edge_edge, "edge-edge");
  check_derivatives(DistanceType::point_plane, "point-plane");

  // Classification: the classified distance is the true one (sampling is
  // an upper bound within its resolution).
  {
    double worst = 0;
    for (unsigned int trial = 0; trial < 40; ++trial)
      {
        const Vec p = random_vec(3), a = random_vec(3), b = random_vec(3),
                  c = random_vec(3), q = random_vec(3);
        const double pe =
          std::sqrt(classify_point_edge(p, a, b).distance_squared);
        const double pt =
          std::sqrt(classify_point_triangle(p, a, b, c).distance_squared);
        const double ee =
          std::sqrt(classify_edge_edge(p, q, a, b).distance_squared);
        for (const auto &r :
             {std::make_pair(pe, sampled_distance({p}, {a, b})),
              std::make_pair(pt, sampled_distance({p}, {a, b, c})),
              std::make_pair(ee, sampled_distance({p, q}, {a, b}))})
          {
            if (r.first > r.second + 1e-12)
              worst = 1;
            worst = std::max(worst, r.second - r.first);
          }
      }
    deallog << "classified distances within sampling resolution: "
            << (worst < 2e-3 ? "yes" : "no") << std::endl;
    // The classes of a point against a triangle and of two segments.
    const Vec o, x{{1., 0., 0.}}, y{{0., 1., 0.}}, z{{0., 0., 1.}};
    deallog << "point-triangle types (face, edge, vertex): "
            << int(classify_point_triangle(0.2 * x + 0.2 * y + z, o, x, y).type)
            << ' '
            << int(classify_point_triangle(0.5 * x - y + z, o, x, y).type)
            << ' ' << int(classify_point_triangle(-x - y + z, o, x, y).type)
            << std::endl;
    deallog
      << "edge-edge types (crossing, parallel, end points): "
      << int(classify_edge_edge(o, x, 0.5 * x - y + z, 0.5 * x + y + z).type)
      << ' ' << int(classify_edge_edge(o, x, z, z + x).type) << ' '
      << int(classify_edge_edge(o, x, 2 * x + z, 3 * x + y).type) << std::endl;
  }

  // Barrier and mollifiers.
  {
    const double dhat = 0.1, h = 1e-7;
    deallog << "b(dhat) = " << barrier(dhat, dhat)
            << ", b'(dhat) = " << barrier_derivative(dhat, dhat)
            << ", b''(dhat/2) = " << barrier_second_derivative(dhat / 2, dhat)
            << std::endl;
    double worst = 0;
    for (const double d : {0.001, 0.01, 0.05, 0.09})
      {
        const double fd1 =
          (barrier(d + h, dhat) - barrier(d - h, dhat)) / (2 * h);
        const double fd2 =
          (barrier_derivative(d + h, dhat) - barrier_derivative(d - h, dhat)) /
          (2 * h);
        worst = std::max(
          {worst,
           std::abs(fd1 - barrier_derivative(d, dhat)) / std::abs(fd1),
           std::abs(fd2 - barrier_second_derivative(d, dhat)) / std::abs(fd2)});
      }
    deallog << "barrier derivatives vs differences: "
            << (worst < 1e-5 ? "ok" : "FAILED") << std::endl;
    const double eta = 0.01;
    deallog << "f0(eta-), f0(eta+): " << friction_f0(eta * (1 - 1e-12), eta)
            << ' ' << friction_f0(eta, eta)
            << "; f1(eta-), f1(0): " << friction_f1(eta * (1 - 1e-12), eta)
            << ' ' << friction_f1(0., eta) << std::endl;
    double worst_f = 0;
    for (const double y : {0.001, 0.005, 0.02})
      {
        const double fd =
          (friction_f0(y + h, eta) - friction_f0(y - h, eta)) / (2 * h);
        worst_f = std::max(worst_f, std::abs(fd - friction_f1(y, eta)));
        worst_f = std::max(worst_f,
                           std::abs(friction_f1_over_y(y, eta) -
                                    friction_f1(y, eta) / y));
      }
    deallog << "friction f1 = f0', f1/y: " << (worst_f < 1e-6 ? "ok" : "FAILED")
            << std::endl;
    deallog << "edge mollifier m(0), m(eps/2), m(eps): "
            << edge_edge_mollifier(0., 1.) << ' '
            << edge_edge_mollifier(0.5, 1.) << ' '
            << edge_edge_mollifier(1., 1.) << std::endl;
  }

  // CCD on constructed cases: time <= true impact time (and not far below).
  {
    const auto report = [](const char               *name,
                           const PairKind            kind,
                           const std::array<Vec, 4> &x,
                           const std::array<Vec, 4> &dx,
                           const double              truth) {
      const CcdResult r = additive_ccd(kind, x, dx);
      deallog << name << ": toi " << r.time << " (true " << truth << "), "
              << (r.time <= truth ? "conservative" : "LATE") << std::endl;
    };
    const Vec o, x{{1., 0., 0.}}, y{{0., 1., 0.}}, z{{0., 0., 1.}};
    report("2D point onto edge",
           PairKind::point_edge,
           {{0.5 * x + y, o, x, o}},
           {{-2 * y, o, o, o}},
           0.5);
    report("2D point through an edge end point",
           PairKind::point_edge,
           {{x + y, o, x, o}},
           {{-2 * y, o, o, o}},
           0.5);
    report("2D grazing point (stays 1e-3 away)",
           PairKind::point_edge,
           {{-x + 1e-3 * y, o, x, o}},
           {{3 * x, o, o, o}},
           1.);
    report("2D edge turning onto a point",
           PairKind::point_edge,
           {{0.5 * x + 0.25 * y, o, x + y, o}},
           {{o, o, -2 * y, o}},
           0.25);
    report("3D point onto triangle",
           PairKind::point_triangle,
           {{0.2 * x + 0.2 * y + z, o, x, y}},
           {{-4 * z, o, o, o}},
           0.25);
    report("3D crossing edges",
           PairKind::edge_edge,
           {{0.5 * x - y + z, 0.5 * x + y + z, o, x}},
           {{-2 * z, -2 * z, o, o}},
           0.5);
    report("3D parallel edges",
           PairKind::edge_edge,
           {{z, z + x, o, x}},
           {{-2 * z, -2 * z, o, o}},
           0.5);
    report("3D parallel edges sliding (no contact)",
           PairKind::edge_edge,
           {{1e-3 * z, 1e-3 * z + x, o, x}},
           {{5 * x, 5 * x, o, o}},
           1.);
    report("plane",
           PairKind::point_plane,
           {{z, o, z, o}},
           {{-4 * z, o, o, o}},
           0.25);

    // Random 2D point-edge trajectories with exact impact times: the
    // orientation (p - a) x (b - a) is quadratic in t.
    unsigned int late = 0, n_hits = 0, n_half = 0;
    for (unsigned int trial = 0; trial < 2000; ++trial)
      {
        std::array<Vec, 4> X{
          {random_vec(2), random_vec(2), random_vec(2), Vec()}};
        std::array<Vec, 4> dX{
          {random_vec(2) * 2, random_vec(2), random_vec(2), Vec()}};
        const auto cross = [&](double t) {
          const Vec p = X[0] + t * dX[0], a = X[1] + t * dX[1],
                    b = X[2] + t * dX[2];
          return (p[0] - a[0]) * (b[1] - a[1]) - (p[1] - a[1]) * (b[0] - a[0]);
        };
        const auto inside = [&](double t) {
          const Vec p = X[0] + t * dX[0], a = X[1] + t * dX[1],
                    b    = X[2] + t * dX[2];
          const double s = (p - a) * (b - a) / (b - a).norm_square();
          return s >= 0 && s <= 1;
        };
        // c(t) = c0 + c1 t + c2 t^2 from three samples.
        const double        c0 = cross(0), ch = cross(0.5), c1_ = cross(1);
        const double        c2 = 2 * (c1_ - 2 * ch + c0), c1 = c1_ - c0 - c2;
        double              truth = 1;
        std::vector<double> roots;
        if (std::abs(c2) < 1e-14)
          roots.push_back(-c0 / c1);
        else
          {
            const double disc = c1 * c1 - 4 * c2 * c0;
            if (disc >= 0)
              {
                roots.push_back((-c1 - std::sqrt(disc)) / (2 * c2));
                roots.push_back((-c1 + std::sqrt(disc)) / (2 * c2));
              }
          }
        for (const double t : roots)
          if (t >= 0 && t <= 1 && inside(t))
            truth = std::min(truth, t);
        const double t = additive_ccd(PairKind::point_edge, X, dX).time;
        if (truth < 1)
          {
            ++n_hits;
            n_half += t >= 0.5 * truth ? 1 : 0;
          }
        late += t > truth + 1e-12 ? 1 : 0;
      }
    deallog << "random 2D trajectories: " << n_hits
            << " impacts, CCD later than the truth: " << late
            << ", CCD time at least half the truth: " << n_half << std::endl;
  }

  // Broad phase against brute force.
  {
    std::vector<Box> a(300), b(200);
    for (auto *set : {&a, &b})
      for (Box &x : *set)
        {
          x.add(random_vec(3));
          x.inflate(uniform(0, 0.1));
        }
    std::set<std::pair<unsigned int, unsigned int>> brute, brute_self;
    for (unsigned int i = 0; i < a.size(); ++i)
      {
        for (unsigned int j = 0; j < b.size(); ++j)
          if (a[i].overlaps(b[j]))
            brute.emplace(i, j);
        for (unsigned int j = i + 1; j < a.size(); ++j)
          if (a[i].overlaps(a[j]))
            brute_self.emplace(i, j);
      }
    const auto p = overlapping_pairs(a, b), q = overlapping_pairs(a);
    deallog
      << "broad phase: " << p.size() << " pairs, brute force " << brute.size()
      << ", identical: "
      << (std::set<std::pair<unsigned int, unsigned int>>(p.begin(), p.end()) ==
              brute ?
            "yes" :
            "no")
      << "; within one set " << q.size() << ", identical: "
      << (std::set<std::pair<unsigned int, unsigned int>>(q.begin(), q.end()) ==
              brute_self ?
            "yes" :
            "no")
      << std::endl;
  }
}
