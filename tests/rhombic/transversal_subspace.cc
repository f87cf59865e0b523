// The pieces of the thesis's transversal-subspace map construction
// (ch. 4.6.2) against known answers:
// - a linear map R^5 -> R^4 with a known null direction w: the fitted V is
//   perpendicular to w (|cos| = 1), the model fits exactly, the fifth
//   singular value vanishes, and V's points satisfy w . (x - origin) = 0;
//   with a mild nonlinearity added, the direction is still found closely;
// - the simplex inverse of an affine map of R^4 with negative determinant
//   is exact; of a map folded at x0 = 0.7, the minority orientation
//   (the fold's far side) is dropped and the near preimage returned;
// - of smooth nonlinear maps of R^2 and R^4, its error falls at rate 2
//   with the grid spacing (linear interpolation; RMS over 64 points).

#include <forma/rhombic/transversal_subspace.h>

#include "../tests.h"

#include <cmath>
#include <functional>

using namespace dealii;
using namespace forma::rhombic;

namespace
{
  using Map = std::function<std::vector<double>(const std::vector<double> &)>;

  std::vector<std::vector<double>>
  axes(const unsigned int dim, const unsigned int n)
  {
    std::vector<double> a(n);
    for (unsigned int i = 0; i < n; ++i)
      a[i] = double(i) / (n - 1);
    return std::vector<std::vector<double>>(dim, a);
  }

  /// The map on the grid of `axes(dim, n)`, last axis fastest.
  SimplexInverse
  sampled(const Map &h, const unsigned int dim, const unsigned int n)
  {
    std::vector<std::optional<std::vector<double>>> values;
    unsigned int                                    total = 1;
    for (unsigned int d = 0; d < dim; ++d)
      total *= n;
    for (unsigned int k = 0; k < total; ++k)
      {
        std::vector<double> x(dim);
        for (unsigned int d = 0, r = k; d < dim; ++d, r /= n)
          x[dim - 1 - d] = double(r % n) / (n - 1);
        values.push_back(h(x));
      }
    return SimplexInverse(axes(dim, n), values);
  }

  /// RMS of |x - x*| over interior points x* with q = h(x*).
  double
  error(const SimplexInverse                   &inverse,
        const Map                              &h,
        const std::vector<std::vector<double>> &points)
  {
    double e = 0;
    for (const auto &x : points)
      {
        const auto y = inverse.preimage(h(x));
        if (!y)
          return 1e300;
        for (unsigned int d = 0; d < x.size(); ++d)
          e += std::pow((*y)[d] - x[d], 2) / points.size();
      }
    return std::sqrt(e);
  }

  /// 64 interior points, spread evenly (a Kronecker sequence).
  std::vector<std::vector<double>>
  points(const unsigned int dim)
  {
    std::vector<std::vector<double>> p;
    for (unsigned int k = 1; k <= 64; ++k)
      {
        std::vector<double> x(dim);
        for (unsigned int d = 0; d < dim; ++d)
          x[d] = 0.15 + 0.7 * std::fmod(k * std::sqrt(2. + 3 * d), 1.);
        p.push_back(x);
      }
    return p;
  }

  void
  rates(const std::string              &name,
        const Map                      &h,
        const unsigned int              dim,
        const std::vector<unsigned int> ns)
  {
    double previous     = 0;
    bool   second_order = true;
    for (const unsigned int n : ns)
      {
        const double e = error(sampled(h, dim, n), h, points(dim));
        if (previous > 0)
          {
            const double rate = std::log2(previous / e);
            second_order      = second_order && std::abs(rate - 2) < 0.3;
          }
        previous = e;
      }
    deallog << name << ": " << ns.size() - 1
            << " halvings of the spacing, every rate within 0.3 of 2: "
            << (second_order ? "yes" : "NO") << std::endl;
  }
} // namespace

int
main()
{
  initlog();

  // A linear map with null direction w.
  const std::vector<double> w       = {0.6, 0., 0., -0.8, 0.};
  const double              B[4][5] = {{1, 2, 0, 1, 3},
                                       {0, 1, 4, 1, 0},
                                       {2, 0, 1, 0, 1},
                                       {1, 1, 1, 2, -1}};
  for (const double bend : {0., 0.02})
    {
      std::vector<std::vector<double>> x, h;
      for (unsigned int k = 0; k < 243; ++k)
        {
          std::vector<double> p(5);
          for (unsigned int d = 0, r = k; d < 5; ++d, r /= 3)
            p[d] = 0.5 * (r % 3);
          double wp = 0;
          for (unsigned int d = 0; d < 5; ++d)
            wp += w[d] * p[d];
          std::vector<double> v(4, 0.);
          for (unsigned int i = 0; i < 4; ++i)
            for (unsigned int d = 0; d < 5; ++d)
              v[i] += B[i][d] * (p[d] - wp * w[d]) + bend * p[d] * p[i];
          x.push_back(p), h.push_back(v);
        }
      const std::vector<double> origin = {0.5, 0.5, 0.5, 0.5, 0.5};
      const auto                V      = fit_transversal_subspace(x, h, origin);
      double                    cos    = 0;
      for (unsigned int d = 0; d < 5; ++d)
        cos += V.normals[0][d] * w[d];
      const auto y   = V.point({0.1, 0.9, 0.3, 0.7});
      double     off = 0;
      for (unsigned int d = 0; d < 5; ++d)
        off += w[d] * (y[d] - origin[d]);
      deallog << "linear map + " << bend << " x_i x_d: " << V.normals.size()
              << " normal, |cos(normal, w)| "
              << (std::abs(std::abs(cos) - 1) < (bend == 0 ? 1e-10 : 2e-3) ?
                    "= 1" :
                    "WRONG " + std::to_string(cos))
              << ", fit residual "
              << (V.fit_residual < (bend == 0 ? 1e-10 : 0.05) ? "small" :
                                                                "LARGE")
              << ", sigma_5 / sigma_4 "
              << (V.singular_values[4] / V.singular_values[3] <
                      (bend == 0 ? 1e-10 : 0.01) ?
                    "small" :
                    "LARGE")
              << ", dependent p" << V.dependent[0] + 1
              << ", |w . (x - origin)| on V "
              << (std::abs(off) < (bend == 0 ? 1e-12 : 0.01) ? "small" :
                                                               "LARGE")
              << std::endl;
    }

  // Affine, orientation reversing.
  const Map affine = [](const std::vector<double> &x) {
    return std::vector<double>{2 * x[1] + 0.1 * x[2],
                               x[0] - x[3],
                               0.5 * x[2] + x[0],
                               x[3] + 0.3 * x[1]};
  };
  {
    const auto   inverse = sampled(affine, 4, 3);
    const double e       = error(inverse, affine, points(4));
    deallog << "affine R^4: " << inverse.n_kept() << " simplices kept, "
            << inverse.n_flipped() << " flipped, error "
            << (e < 1e-12 ? "< 1e-12" : "LARGE") << ", outside the image: "
            << (inverse.preimage({5, 5, 5, 5}) ? "found" : "none") << std::endl;
  }

  // Folded at x0 = 0.7: x0 = 0.5 and 0.9 give the same value.
  const Map folded = [](const std::vector<double> &x) {
    return std::vector<double>{std::abs(x[0] - 0.7), x[1], x[2] + 0.2 * x[0]};
  };
  {
    const auto inverse = sampled(folded, 3, 11);
    const auto y       = inverse.preimage(folded({0.5, 0.4, 0.3}));
    deallog << "folded R^3: " << inverse.n_kept() << " kept, "
            << inverse.n_flipped() << " flipped, preimage x0 "
            << (y ? std::to_string(std::round(100 * (*y)[0]) / 100) : "none")
            << std::endl;
  }

  rates("nonlinear R^2",
        [](const std::vector<double> &x) {
          return std::vector<double>{x[0] + 0.3 * x[1] * x[1] +
                                       0.1 * std::sin(3 * x[0]),
                                     x[1] + 0.2 * x[0] * x[1]};
        },
        2,
        {5, 9, 17, 33});
  rates("nonlinear R^4",
        [](const std::vector<double> &x) {
          return std::vector<double>{x[0] + 0.2 * x[1] * x[1],
                                     x[1] + 0.1 * std::sin(2 * x[2]),
                                     x[2] + 0.2 * x[3] * x[0],
                                     x[3] + 0.1 * x[0] * x[0]};
        },
        4,
        {3, 5, 9});
}
