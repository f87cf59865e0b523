#include <deal.II/base/exceptions.h>

#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/parallelogram_cell.h>

#include <cmath>

namespace forma
{
  using namespace dealii;

  ParallelogramCell::ParallelogramCell(const Tensor<2, 2> &F)
    : F(F)
  {
    AssertThrow(std::abs(determinant(F)) > 1e-12 * F.norm_square(),
                ExcMessage("a parallelogram cell needs independent sides"));
    G = invert(F);
  }



  SymmetricTensor<4, 2>
  ParallelogramCell::to_reference(const SymmetricTensor<4, 2> &C) const
  {
    return transform(C, G);
  }



  SymmetricTensor<4, 2>
  ParallelogramCell::from_reference(
    const SymmetricTensor<4, 2> &C_reference) const
  {
    return transform(C_reference, F);
  }
} // namespace forma
