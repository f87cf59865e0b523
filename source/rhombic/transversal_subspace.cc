#include <deal.II/base/exceptions.h>
#include <deal.II/lac/exceptions.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <forma/rhombic/transversal_subspace.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    namespace
    {
      /// Invert the n x n row-major matrix `a` in place (LAPACK's LU);
      /// returns its determinant, 0 if singular.
      double
      invert(std::vector<double> &a, const unsigned int n)
      {
        LAPACKFullMatrix<double> m(n, n);
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = 0; j < n; ++j)
            m(i, j) = a[i * n + j];
        try
          {
            m.compute_lu_factorization();
          }
        catch (const LACExceptions::ExcSingular &)
          {
            return 0;
          }
        const double det = m.determinant();
        m.invert();
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = 0; j < n; ++j)
            a[i * n + j] = m(i, j);
        return det;
      }
    } // namespace



    std::vector<double>
    TransversalSubspace::point(const std::vector<double> &values) const
    {
      AssertThrow(values.size() == coordinates.size(),
                  ExcMessage("TransversalSubspace: " +
                             std::to_string(coordinates.size()) +
                             " coordinate values expected"));
      std::vector<double> x(origin.size(), 0.);
      for (unsigned int i = 0; i < coordinates.size(); ++i)
        x[coordinates[i]] = values[i];
      // W_D^T x_D = W^T origin - W_F^T x_F
      const unsigned int  k = dependent.size();
      std::vector<double> a(k * k), rhs(k, 0.);
      for (unsigned int r = 0; r < k; ++r)
        {
          for (unsigned int j = 0; j < origin.size(); ++j)
            rhs[r] += normals[r][j] * (origin[j] - x[j]);
          for (unsigned int c = 0; c < k; ++c)
            a[r * k + c] = normals[r][dependent[c]];
        }
      AssertThrow(k == 0 || invert(a, k) != 0,
                  ExcInternalError("singular dependent block"));
      for (unsigned int r = 0; r < k; ++r)
        {
          double v = 0;
          for (unsigned int c = 0; c < k; ++c)
            v += a[r * k + c] * rhs[c];
          x[dependent[r]] = v;
        }
      return x;
    }



    TransversalSubspace
    fit_transversal_subspace(const std::vector<std::vector<double>> &x,
                             const std::vector<std::vector<double>> &h,
                             const std::vector<double>              &origin)
    {
      AssertThrow(!x.empty() && x.size() == h.size(),
                  ExcMessage("transversal subspace: as many outputs as "
                             "samples needed"));
      const unsigned int n = x[0].size(), m = h[0].size();
      AssertThrow(m < n && origin.size() == n,
                  ExcMessage("transversal subspace: fewer outputs than "
                             "parameters needed, and an origin with as many "
                             "entries as parameters"));
      AssertThrow(x.size() > n,
                  ExcMessage(
                    "transversal subspace: " + std::to_string(x.size()) +
                    " samples cannot fit a linear model in " +
                    std::to_string(n) + " parameters"));

      // Outputs scaled to unit spread, so that no modulus dominates the SVD.
      std::vector<double> x_mean(n, 0.), h_mean(m, 0.), h_spread(m, 0.);
      for (unsigned int s = 0; s < x.size(); ++s)
        {
          for (unsigned int j = 0; j < n; ++j)
            x_mean[j] += x[s][j] / x.size();
          for (unsigned int i = 0; i < m; ++i)
            h_mean[i] += h[s][i] / x.size();
        }
      for (unsigned int s = 0; s < x.size(); ++s)
        for (unsigned int i = 0; i < m; ++i)
          h_spread[i] += std::pow(h[s][i] - h_mean[i], 2) / x.size();
      for (auto &v : h_spread)
        v = std::max(std::sqrt(v), 1e-300);

      // Least squares, H(x) - h_mean ~ Q (x - x_mean): the normal equations.
      FullMatrix<double> AtA(n, n), AtB(n, m);
      for (unsigned int s = 0; s < x.size(); ++s)
        for (unsigned int j = 0; j < n; ++j)
          {
            const double xj = x[s][j] - x_mean[j];
            for (unsigned int k = 0; k < n; ++k)
              AtA(j, k) += xj * (x[s][k] - x_mean[k]);
            for (unsigned int i = 0; i < m; ++i)
              AtB(j, i) += xj * (h[s][i] - h_mean[i]) / h_spread[i];
          }
      FullMatrix<double> coefficients(n, m);
      {
        FullMatrix<double> inverse(n, n);
        inverse.copy_from(AtA);
        AssertThrow(inverse.frobenius_norm() > 0,
                    ExcMessage("transversal subspace: the samples do not "
                               "vary the parameters"));
        inverse.gauss_jordan();
        inverse.mmult(coefficients, AtB);
      }
      TransversalSubspace V;
      V.origin        = origin;
      double residual = 0;
      for (unsigned int s = 0; s < x.size(); ++s)
        for (unsigned int i = 0; i < m; ++i)
          {
            double model = 0;
            for (unsigned int j = 0; j < n; ++j)
              model += coefficients(j, i) * (x[s][j] - x_mean[j]);
            residual +=
              std::pow((h[s][i] - h_mean[i]) / h_spread[i] - model, 2);
          }
      V.fit_residual = std::sqrt(residual / (x.size() * m));

      // Q padded with zero rows to n x n: its SVD gives all of V^T, whose
      // last n - m rows span the null space.
      LAPACKFullMatrix<double> Q(n, n);
      for (unsigned int i = 0; i < m; ++i)
        for (unsigned int j = 0; j < n; ++j)
          Q(i, j) = coefficients(j, i);
      Q.compute_svd();
      for (unsigned int i = 0; i < n; ++i)
        V.singular_values.push_back(Q.singular_value(i));
      const auto &vt = Q.get_svd_vt();
      for (unsigned int r = m; r < n; ++r)
        {
          std::vector<double> w(n);
          for (unsigned int j = 0; j < n; ++j)
            w[j] = vt(r, j);
          // A sign convention, for reproducible output: largest entry > 0.
          const auto big = std::max_element(w.begin(),
                                            w.end(),
                                            [](const double a, const double b) {
                                              return std::abs(a) < std::abs(b);
                                            });
          if (*big < 0)
            for (auto &v : w)
              v = -v;
          V.normals.push_back(w);
        }

      // The dependent coordinates: complete pivoting on W^T, so that the
      // block solved in point() is as well conditioned as it can be.
      std::vector<std::vector<double>> w = V.normals;
      std::vector<bool>                taken(n, false);
      for (unsigned int r = 0; r < w.size(); ++r)
        {
          unsigned int best = n;
          for (unsigned int j = 0; j < n; ++j)
            if (!taken[j] &&
                (best == n || std::abs(w[r][j]) > std::abs(w[r][best])))
              best = j;
          taken[best] = true;
          V.dependent.push_back(best);
          for (unsigned int q = r + 1; q < w.size(); ++q)
            {
              const double f = w[q][best] / w[r][best];
              for (unsigned int j = 0; j < n; ++j)
                w[q][j] -= f * w[r][j];
            }
        }
      for (unsigned int j = 0; j < n; ++j)
        if (!taken[j])
          V.coordinates.push_back(j);
      return V;
    }



    SimplexInverse::SimplexInverse(
      const std::vector<std::vector<double>>                &axes,
      const std::vector<std::optional<std::vector<double>>> &values)
      : dim(axes.size())
    {
      AssertThrow(dim >= 1, ExcMessage("SimplexInverse: no axes"));
      std::vector<unsigned int> stride(dim, 1);
      for (int d = dim - 2; d >= 0; --d)
        stride[d] = stride[d + 1] * axes[d + 1].size();
      AssertThrow(values.size() == stride[0] * axes[0].size(),
                  ExcMessage(
                    "SimplexInverse: " + std::to_string(values.size()) +
                    " values for a grid of " +
                    std::to_string(stride[0] * axes[0].size()) + " points"));
      for (const auto &a : axes)
        AssertThrow(a.size() >= 2 && std::is_sorted(a.begin(), a.end()) &&
                      std::adjacent_find(a.begin(), a.end()) == a.end(),
                    ExcMessage("SimplexInverse: every axis needs at least "
                               "two increasing values"));
      for (const auto &v : values)
        AssertThrow(!v || v->size() == dim,
                    ExcMessage("SimplexInverse: the map must go from R^m to "
                               "R^m"));

      std::vector<unsigned int> cell(dim, 0);
      std::vector<Simplex>      positive, negative;
      bool                      more = true;
      while (more)
        {
          std::vector<unsigned int> order(dim);
          std::iota(order.begin(), order.end(), 0);
          do
            {
              // Corners: the cell's first grid point, then one step along
              // each axis in the order's sequence.
              std::vector<unsigned int> corner = cell, flat{0};
              for (unsigned int d = 0; d < dim; ++d)
                flat[0] += cell[d] * stride[d];
              for (unsigned int j = 0; j < dim; ++j)
                {
                  ++corner[order[j]];
                  flat.push_back(flat.back() + stride[order[j]]);
                }
              if (std::any_of(flat.begin(), flat.end(), [&](unsigned int f) {
                    return !values[f];
                  }))
                continue;
              Simplex s;
              s.h0 = *values[flat[0]];
              s.x0.resize(dim);
              for (unsigned int d = 0; d < dim; ++d)
                s.x0[d] = axes[d][cell[d]];
              s.dx.assign(dim * dim, 0.);
              s.inverse.resize(dim * dim);
              double scale = 0;
              for (unsigned int j = 0; j < dim; ++j)
                {
                  for (unsigned int l = 0; l <= j; ++l)
                    s.dx[order[l] * dim + j] =
                      axes[order[l]][cell[order[l]] + 1] -
                      axes[order[l]][cell[order[l]]];
                  double norm = 0;
                  for (unsigned int i = 0; i < dim; ++i)
                    {
                      s.inverse[i * dim + j] =
                        (*values[flat[j + 1]])[i] - s.h0[i];
                      norm += std::pow(s.inverse[i * dim + j], 2);
                    }
                  scale = std::max(scale, std::sqrt(norm));
                }
              const double det = invert(s.inverse, dim);
              if (std::abs(det) <= 1e-12 * std::pow(scale, dim))
                continue;
              // The grid simplex's own orientation is the parity of the
              // order.
              unsigned int inversions = 0;
              for (unsigned int a = 0; a < dim; ++a)
                for (unsigned int b = a + 1; b < dim; ++b)
                  inversions += order[a] > order[b];
              ((det > 0) == (inversions % 2 == 0) ? positive : negative)
                .push_back(std::move(s));
          } while (std::next_permutation(order.begin(), order.end()));

          more = false;
          for (int d = dim - 1; d >= 0; --d)
            if (++cell[d] + 1 < axes[d].size())
              {
                more = true;
                break;
              }
            else
              cell[d] = 0;
        }
      if (negative.size() > positive.size())
        std::swap(positive, negative);
      simplices = std::move(positive);
      flipped   = negative.size();
    }



    std::optional<std::vector<double>>
    SimplexInverse::preimage(const std::vector<double> &q) const
    {
      AssertThrow(q.size() == dim,
                  ExcMessage("SimplexInverse: a value with " +
                             std::to_string(dim) + " entries expected"));
      const Simplex      *best  = nullptr;
      double              depth = -1e-10;
      std::vector<double> lambda(dim), best_lambda;
      unsigned int        inside = 0;
      for (const auto &s : simplices)
        {
          double first = 1, lowest = 1e300;
          for (unsigned int i = 0; i < dim; ++i)
            {
              lambda[i] = 0;
              for (unsigned int k = 0; k < dim; ++k)
                lambda[i] += s.inverse[i * dim + k] * (q[k] - s.h0[k]);
              first -= lambda[i];
              lowest = std::min(lowest, lambda[i]);
            }
          lowest = std::min(lowest, first);
          if (lowest > 1e-8)
            ++inside;
          if (lowest >= depth)
            best = &s, depth = lowest, best_lambda = lambda;
        }
      if (inside > 1)
        ++ambiguous;
      if (best == nullptr)
        return {};
      std::vector<double> x = best->x0;
      for (unsigned int d = 0; d < dim; ++d)
        for (unsigned int j = 0; j < dim; ++j)
          x[d] += best->dx[d * dim + j] * best_lambda[j];
      return x;
    }
  } // namespace rhombic
} // namespace forma
