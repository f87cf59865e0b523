#ifndef forma_solvers_sparse_cholesky_h
#define forma_solvers_sparse_cholesky_h

#include <memory>

namespace dealii
{
  template <typename number>
  class SparseMatrix;
  template <typename number>
  class Vector;
} // namespace dealii

namespace forma
{
  /**
   * Sparse Cholesky factorization LL' (CHOLMOD: simplicial, or supernodal
   * with the BLAS for fill-heavy factors) of a
   * symmetric positive definite deal.II matrix on one process. The
   * fill-reducing analysis is kept across factorize() calls with the same
   * sparsity pattern, so a sweep over many materials on one mesh pays it
   * once. Several times faster than a general LU on 2D elasticity.
   */
  class SparseCholesky
  {
  public:
    SparseCholesky();
    ~SparseCholesky();

    /// Factorize A (its upper triangle is read); throws if A is not
    /// positive definite. Re-analyzes only if the pattern changed.
    void
    factorize(const dealii::SparseMatrix<double> &A);

    /// Solve A x = b in place.
    void
    solve(dealii::Vector<double> &b) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace forma

#endif
