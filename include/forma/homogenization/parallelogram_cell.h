#ifndef forma_homogenization_parallelogram_cell_h
#define forma_homogenization_parallelogram_cell_h

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

namespace forma
{
  /**
   * Homogenization on a parallelogram cell R = F(Q) through the reference
   * square Q (thesis ch. 4.5.2, Proposition 1). With the fluctuation written
   * in the basis of R's sides, the cell problem on R is the cell problem on Q
   * with the tensor C'_ijkl = G_ip G_jq G_kr G_lt C_pqrt, G = F^-1 (eq. 4.6),
   * and the effective tensors are related by the inverse rule with F
   * (eq. 4.7); the energy densities agree because a macroscopic strain E on
   * R is the strain F^T E F on Q. So: transform the materials with
   * to_reference(), homogenize on Q, and map the result back with
   * from_reference().
   */
  class ParallelogramCell
  {
  public:
    /// F maps Q onto R (its columns are R's side vectors divided by Q's
    /// side length); it must be invertible.
    explicit ParallelogramCell(const dealii::Tensor<2, 2> &F);

    /// Eq. 4.6: a material of R as seen on Q.
    dealii::SymmetricTensor<4, 2>
    to_reference(const dealii::SymmetricTensor<4, 2> &C) const;

    /// Eq. 4.7: an effective tensor computed on Q, in R's coordinates.
    dealii::SymmetricTensor<4, 2>
    from_reference(const dealii::SymmetricTensor<4, 2> &C_reference) const;

    const dealii::Tensor<2, 2> &
    map() const
    {
      return F;
    }

  private:
    dealii::Tensor<2, 2> F, G;
  };
} // namespace forma

#endif
