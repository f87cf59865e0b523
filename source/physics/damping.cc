#include <deal.II/base/symmetric_tensor.h>

#include <forma/physics/damping.h>

namespace forma
{
  using namespace dealii;

  namespace
  {
    // F, the backward-difference rate dF and the Green strain rate dE.
    template <int dim>
    struct Kinematics
    {
      Kinematics(const Tensor<2, dim> &grad_u,
                 const Tensor<2, dim> &grad_u_old,
                 const double          dt)
        : F(grad_u + unit_symmetric_tensor<dim>())
        , F_dot((grad_u - grad_u_old) / dt)
        , E_dot(0.5 * (transpose(F_dot) * F + transpose(F) * F_dot))
      {}
      const Tensor<2, dim> F, F_dot, E_dot;
    };
  } // namespace



  template <int dim>
  Tensor<2, dim>
  Damping<dim>::stress(const Tensor<2, dim> &grad_u,
                       const Tensor<2, dim> &grad_u_old,
                       const double          dt) const
  {
    const Kinematics<dim> k(grad_u, grad_u_old, dt);
    return k.F * (2. * alpha * k.E_dot +
                  beta * trace(k.E_dot) * unit_symmetric_tensor<dim>());
  }



  template <int dim>
  double
  Damping<dim>::dissipation_potential(const Tensor<2, dim> &grad_u,
                                      const Tensor<2, dim> &grad_u_old,
                                      const double          dt) const
  {
    const Tensor<2, dim> I = unit_symmetric_tensor<dim>();
    const Tensor<2, dim> F = I + grad_u, F_old = I + grad_u_old;
    const Tensor<2, dim> dE =
      0.5 * (transpose(F) * F - transpose(F_old) * F_old);
    return (alpha * scalar_product(dE, dE) +
            0.5 * beta * trace(dE) * trace(dE)) /
           dt;
  }



  template <int dim>
  Tensor<4, dim>
  Damping<dim>::derivative(const Tensor<2, dim> &grad_u,
                           const Tensor<2, dim> &grad_u_old,
                           const double          dt,
                           const bool            current) const
  {
    // Directional derivatives along the unit tensors e_k (x) e_l.
    const Tensor<2, dim>  I = unit_symmetric_tensor<dim>();
    const Kinematics<dim> kin(grad_u, grad_u_old, dt);
    const Tensor<2, dim> &F     = kin.F;
    const Tensor<2, dim> &F_dot = kin.F_dot;
    const Tensor<2, dim>  S =
      2. * alpha * kin.E_dot + beta * trace(kin.E_dot) * I;

    Tensor<4, dim> D;
    for (unsigned int k = 0; k < dim; ++k)
      for (unsigned int l = 0; l < dim; ++l)
        {
          Tensor<2, dim> H;
          H[k][l]                     = 1.;
          const Tensor<2, dim> dF     = current ? H : Tensor<2, dim>();
          const Tensor<2, dim> dF_dot = (current ? 1. : -1.) / dt * H;
          const Tensor<2, dim> dE_dot =
            0.5 * (transpose(dF_dot) * F + transpose(F_dot) * dF +
                   transpose(dF) * F_dot + transpose(F) * dF_dot);
          const Tensor<2, dim> dS =
            2. * alpha * dE_dot + beta * trace(dE_dot) * I;
          const Tensor<2, dim> dP = dF * S + F * dS;
          for (unsigned int i = 0; i < dim; ++i)
            for (unsigned int j = 0; j < dim; ++j)
              D[i][j][k][l] = dP[i][j];
        }
    return D;
  }



  template <int dim>
  Tensor<4, dim>
  Damping<dim>::tangent(const Tensor<2, dim> &grad_u,
                        const Tensor<2, dim> &grad_u_old,
                        const double          dt) const
  {
    return derivative(grad_u, grad_u_old, dt, true);
  }



  template <int dim>
  Tensor<4, dim>
  Damping<dim>::tangent_old(const Tensor<2, dim> &grad_u,
                            const Tensor<2, dim> &grad_u_old,
                            const double          dt) const
  {
    return derivative(grad_u, grad_u_old, dt, false);
  }

  template class Damping<2>;
  template class Damping<3>;
} // namespace forma
