#ifndef forma_physics_contractions_h
#define forma_physics_contractions_h

#include <deal.II/base/tensor.h>

namespace forma
{
  /// H_kl = sum_ij G_ij A_ijkl: the adjoint gradient G through a tangent A.
  template <int dim>
  inline dealii::Tensor<2, dim>
  contract_left(const dealii::Tensor<2, dim> &G,
                const dealii::Tensor<4, dim> &A)
  {
    dealii::Tensor<2, dim> H;
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = 0; j < dim; ++j)
        if (G[i][j] != 0)
          H += G[i][j] * A[i][j];
    return H;
  }

  /**
   * Shape-derivative kernel of an integrand of grad u transported with the
   * domain: d/d eps grad u = -grad u grad theta, so
   *   D : (-grad u grad theta) = -sum_l (sum_k D_kl gu_kc) dN_l
   * for theta = N e_c; returned as rows c of the tensor W_cl.
   */
  template <int dim>
  inline dealii::Tensor<2, dim>
  transport_kernel(const dealii::Tensor<2, dim> &D,
                   const dealii::Tensor<2, dim> &grad_u)
  {
    return -transpose(grad_u) * D;
  }

  /// sum_l M[c][l] g[l]: M contracted with the rank-one gradient e_c (x) g.
  template <int dim>
  inline double
  row_dot(const dealii::Tensor<2, dim> &M,
          const unsigned int            c,
          const dealii::Tensor<1, dim> &g)
  {
    return M[c] * g;
  }
} // namespace forma

#endif
