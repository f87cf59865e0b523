// SparseCholesky against an independent solver: a 2D five-point operator
// plus a pseudo-random symmetric coupling (SPD by diagonal dominance),
// assembled through add_row() with whole rows (the transposed half it must
// skip) and a column repeated within one call, is factorized and solved;
// UMFPACK solves the same matrix assembled as a deal.II SparseMatrix. Then
// new values on the same pattern (the kept analysis), a new pattern (a new
// analysis), and a matrix that is not positive definite.

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_direct.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <forma/solvers/sparse_cholesky.h>

#include "../tests.h"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>

using namespace dealii;

namespace
{
  /// A reproducible pseudo-random sequence (the standard distributions'
  /// outputs differ between library implementations).
  class Sequence
  {
  public:
    /// In [0, 1).
    double
    next()
    {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      return (state >> 11) * (1. / 9007199254740992.);
    }

  private:
    std::uint64_t state = 7;
  };



  /// The rows of a symmetric matrix on a k x k grid, (column -> value).
  std::vector<std::map<unsigned int, double>>
  make_matrix(const unsigned int k, Sequence &random)
  {
    const unsigned int                          n = k * k;
    std::vector<std::map<unsigned int, double>> A(n);
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
    for (unsigned int e = 0; e < 8 * k; ++e)
      {
        const unsigned int r = random.next() * n, c = random.next() * n;
        if (r != c)
          couple(r, c, 2 * random.next() - 1);
      }
    return A;
  }



  /// Takes A's pattern, then factorizes and solves for scaled values of A
  /// on it, against UMFPACK.
  void
  check(forma::SparseCholesky                             &cholesky,
        const std::vector<std::map<unsigned int, double>> &A)
  {
    const unsigned int     n = A.size();
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
            // One call per row, every column twice (then in reverse order)
            // with half the value.
            std::vector<unsigned int> columns;
            std::vector<double>       values;
            for (const auto &[c, v] : A[r])
              {
                const double value = scale * v + (c == r ? scale - 1 : 0);
                columns.push_back(c);
                values.push_back(0.5 * value);
                reference.add(r, c, value);
              }
            columns.insert(columns.end(), columns.rbegin(), columns.rend());
            values.insert(values.end(), values.rbegin(), values.rend());
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
                << std::endl;
      }
  }
} // namespace



int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  Sequence              random;
  forma::SparseCholesky cholesky;
  check(cholesky, make_matrix(24, random));
  // Another pattern on the same object.
  const auto A = make_matrix(16, random);
  check(cholesky, A);

  // Prints whether `f` throws with `expected` in its message.
  const auto expect_error = [](const std::string           &what,
                               const std::string           &expected,
                               const std::function<void()> &f) {
    std::string result = "no error (wrong)";
    try
      {
        f();
      }
    catch (const std::exception &e)
      {
        result = std::string(e.what()).find(expected) != std::string::npos ?
                   "refused: " + expected :
                   "another error";
      }
    deallog << what << ": " << result << std::endl;
  };
  // -A is not positive definite: a clear error, not a wrong solution.
  cholesky.set_zero();
  for (unsigned int r = 0; r < A.size(); ++r)
    for (const auto &[c, v] : A[r])
      {
        const double value = -v;
        cholesky.add_row(r, 1, &c, &value);
      }
  expect_error("-A", "not positive definite", [&]() { cholesky.factorize(); });
  // An entry outside the pattern, also in release builds.
  const unsigned int r      = A.size() - 1;
  unsigned int       column = 0;
  while (A[r].count(column) > 0)
    ++column;
  const double value = 1;
  expect_error("an entry outside the pattern", "not in the pattern", [&]() {
    cholesky.add_row(r, 1, &column, &value);
  });
}
