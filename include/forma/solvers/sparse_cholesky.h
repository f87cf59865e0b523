#ifndef forma_solvers_sparse_cholesky_h
#define forma_solvers_sparse_cholesky_h

#include <memory>

namespace dealii
{
  class DynamicSparsityPattern;
  template <typename number>
  class Vector;
} // namespace dealii

namespace forma
{
  /**
   * A symmetric positive definite matrix on one process, assembled in
   * place and factorized LL' by CHOLMOD (simplicial, or supernodal with the
   * BLAS for fill-heavy factors). Only the upper triangle is stored, in
   * CHOLMOD's own arrays: no second copy of the matrix, half the entries to
   * add. The fill-reducing analysis is kept across factorize() calls on one
   * pattern, so a sweep over many materials on one mesh pays it once.
   * Several times faster than a general LU on 2D elasticity.
   */
  class SparseCholesky
  {
  public:
    SparseCholesky();
    ~SparseCholesky();

    /// Take the pattern of the matrix (square, symmetric): its entries
    /// (r, c) with c <= r, which are all a caller needs to add. Values
    /// are zero; the next factorize() analyzes the pattern.
    void
    reinit(const dealii::DynamicSparsityPattern &pattern);

    /// Set every value to zero, keeping the pattern and its analysis.
    void
    set_zero();

    /// A(r, c) += values[q] for the c = columns[q] <= r (the others are
    /// the transposed entries, added through their own row); a column may
    /// appear several times. Every entry must be in the pattern.
    void
    add_row(const unsigned int  r,
            const unsigned int  n,
            const unsigned int *columns,
            const double       *values);

    /// The matrix's size.
    unsigned int
    size() const;

    /// Factorize the matrix added; throws if it is not positive definite.
    void
    factorize();

    /// Solve A x = b in place.
    void
    solve(dealii::Vector<double> &b) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace forma

#endif
