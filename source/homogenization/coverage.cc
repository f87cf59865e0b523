#include <deal.II/base/exceptions.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <forma/homogenization/coverage.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace forma
{
  using namespace dealii;

  CoverageCoefficients
  coverage_coefficients(const std::vector<std::array<double, 2>> &samples,
                        const IsotropicModuli                    &base,
                        const double                              level,
                        const double                              band)
  {
    CoverageCoefficients c;
    // E_max(nu) = min(2 kappa_b (1 - nu), 2 mu_b (1 + nu)) equals level E_b.
    c.limit_right = 1 - level * base.E / (2 * base.kappa);
    c.limit_left  = level * base.E / (2 * base.mu) - 1;
    c.nu_right    = -std::numeric_limits<double>::max();
    c.nu_left     = std::numeric_limits<double>::max();
    for (const auto &s : samples)
      if (std::abs(s[1] - level) <= band)
        {
          ++c.n_in_band;
          c.nu_right = std::max(c.nu_right, s[0]);
          c.nu_left  = std::min(c.nu_left, s[0]);
        }
    if (c.n_in_band == 0)
      {
        c.nu_right = c.nu_left = std::numeric_limits<double>::quiet_NaN();
        c.delta_right = c.delta_left = std::numeric_limits<double>::quiet_NaN();
        return c;
      }
    c.delta_right = c.nu_right / c.limit_right;
    c.delta_left  = c.nu_left / c.limit_left;
    return c;
  }



  std::vector<std::array<double, 2>>
  upper_envelope(const std::vector<std::array<double, 2>> &samples,
                 const double                              nu_min,
                 const double                              nu_max,
                 const unsigned int                        n_bins)
  {
    std::vector<double> best(n_bins, -1), at(n_bins, 0);
    for (const auto &s : samples)
      {
        if (s[0] < nu_min || s[0] >= nu_max)
          continue;
        const unsigned int b =
          std::min<unsigned int>(n_bins - 1,
                                 (s[0] - nu_min) / (nu_max - nu_min) * n_bins);
        if (s[1] > best[b])
          {
            best[b] = s[1];
            at[b]   = s[0];
          }
      }
    std::vector<std::array<double, 2>> envelope;
    for (unsigned int b = 0; b < n_bins; ++b)
      if (best[b] >= 0)
        envelope.push_back({{at[b], best[b]}});
    return envelope;
  }



  std::array<double, 3>
  fit_boundary_polynomial(const std::vector<std::array<double, 2>> &points)
  {
    AssertThrow(points.size() >= 3,
                ExcMessage("the boundary polynomial (eq. 5.10) needs at least "
                           "3 envelope points; sample more structures"));
    // E - 1 - nu = c1 (nu + nu^2) + c2 (nu^3 - nu) + c3 (nu + nu^4)
    FullMatrix<double> A(3, 3);
    Vector<double>     b(3), c(3);
    for (const auto &p : points)
      {
        const double nu   = p[0];
        const double f[3] = {nu + nu * nu,
                             nu * nu * nu - nu,
                             nu + nu * nu * nu * nu};
        const double r    = p[1] - 1 - nu;
        for (unsigned int i = 0; i < 3; ++i)
          {
            b(i) += f[i] * r;
            for (unsigned int j = 0; j < 3; ++j)
              A(i, j) += f[i] * f[j];
          }
      }
    FullMatrix<double> A_inv(3, 3);
    A_inv.invert(A);
    A_inv.vmult(c, b);
    return {{c(0), c(1), c(2)}};
  }
} // namespace forma
