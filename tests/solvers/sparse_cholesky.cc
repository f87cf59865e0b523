// SparseCholesky against an independent solver: a 2D five-point operator
// plus a random symmetric coupling (SPD by diagonal dominance), assembled
// through add_row() with whole rows, repeated columns and the transposed
// half it must skip, is factorized and solved; UMFPACK solves the same
// matrix assembled as a deal.II SparseMatrix. Then new values on the same
// pattern (the kept analysis), and a matrix that is not positive definite.

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <forma/solvers/sparse_cholesky.h>

#include "../tests.h"

#include <map>
#include <random>

using namespace dealii;

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  // Rows of a symmetric matrix as (column -> value); n x n grid points.
  const unsigned int                          k = 24, n = k * k;
  std::vector<std::map<unsigned int, double>> A(n);
  std::mt19937                                random(7);
  std::uniform_real_distribution<double>      uniform(-1, 1);
  std::uniform_int_distribution<unsigned int> any(0, n - 1);
  const auto                                  couple =
    [&](const unsigned int r, const unsigned int c, const double v) {
      A[r][c] += v;
      A[c][r] += v;
      A[r][r] += std::abs(v) + 0.05;
      A[c][c] += std::abs(v) + 0.05;
    };
  for (unsigned int i = 0; i < k; ++i)
    for (unsigned int j = 0; j < k; ++j)
      {
        const unsigned int r = i * k + j;
        if (i + 1 < k)
          couple(r, r + k, -1);
        if (j + 1 < k)
          couple(r, r + 1, -1);
      }
  for (unsigned int e = 0; e < 200; ++e)
    {
      const unsigned int r = any(random), c = any(random);
      if (r != c)
        couple(r, c, uniform(random));
    }

  DynamicSparsityPattern lower(n), full(n);
  for (unsigned int r = 0; r < n; ++r)
    for (const auto &[c, v] : A[r])
      {
        full.add(r, c);
        if (c <= r)
          lower.add(r, c);
      }
  SparsityPattern pattern;
  pattern.copy_from(full);
  SparseMatrix<double> reference(pattern);

  forma::SparseCholesky cholesky;
  cholesky.reinit(lower);
  deallog << "size " << cholesky.size() << std::endl;

  Vector<double> b(n);
  for (unsigned int i = 0; i < n; ++i)
    b(i) = std::sin(0.1 * i) + 0.5;

  for (const double scale : {1., 3.})
    {
      cholesky.set_zero();
      reference = 0;
      for (unsigned int r = 0; r < n; ++r)
        {
          // Each value in two halves, the second pass in reverse order.
          std::vector<unsigned int> columns;
          std::vector<double>       values;
          for (const auto &[c, v] : A[r])
            {
              const double value = scale * v + (c == r ? scale - 1 : 0);
              columns.push_back(c);
              values.push_back(0.5 * value);
              reference.add(r, c, value);
            }
          cholesky.add_row(r, columns.size(), columns.data(), values.data());
          std::reverse(columns.begin(), columns.end());
          std::reverse(values.begin(), values.end());
          cholesky.add_row(r, columns.size(), columns.data(), values.data());
        }
      cholesky.factorize();
      Vector<double> x = b;
      cholesky.solve(x);

      SparseDirectUMFPACK umfpack;
      umfpack.initialize(reference);
      Vector<double> y = b;
      umfpack.solve(y);

      Vector<double> residual(n);
      reference.vmult(residual, x);
      residual -= b;
      Vector<double> difference = x;
      difference -= y;
      deallog << "scale " << scale << ": |x - x_umfpack| / |x| < 1e-12: "
              << (difference.l2_norm() < 1e-12 * x.l2_norm() ? "yes" : "no")
              << ", |A x - b| / |b| < 1e-12: "
              << (residual.l2_norm() < 1e-12 * b.l2_norm() ? "yes" : "no")
              << ", |x| = " << x.l2_norm() << std::endl;
    }

  // -A is not positive definite: a clear error, not a wrong solution.
  cholesky.set_zero();
  for (unsigned int r = 0; r < n; ++r)
    for (const auto &[c, v] : A[r])
      {
        const double value = -v;
        cholesky.add_row(r, 1, &c, &value);
      }
  try
    {
      cholesky.factorize();
      deallog << "-A factorized (wrong)" << std::endl;
    }
  catch (const std::exception &e)
    {
      const std::string what = e.what();
      deallog << "-A: "
              << (what.find("not positive definite") != std::string::npos ?
                    "not positive definite" :
                    "other error")
              << std::endl;
    }
}
