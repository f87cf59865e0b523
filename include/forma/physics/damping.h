#ifndef forma_physics_damping_h
#define forma_physics_damping_h

#include <deal.II/base/tensor.h>

namespace forma
{
  /**
   * Strain-rate damping of Brown et al. 2018 (thesis ch. 3.7.2):
   *   P = F (2 alpha dE + beta tr(dE) I),  dE = (dF^T F + F^T dF) / 2,
   * with dF = (F^i - F^{i-1}) / dt, so the force depends on u^i and u^{i-1}.
   */
  template <int dim>
  class Damping
  {
  public:
    Damping(const double alpha, const double beta)
      : alpha(alpha)
      , beta(beta)
    {}

    bool
    active() const
    {
      return alpha > 0 || beta > 0;
    }

    dealii::Tensor<2, dim>
    stress(const dealii::Tensor<2, dim> &grad_u,
           const dealii::Tensor<2, dim> &grad_u_old,
           const double                  dt) const;

    /**
     * The dissipation potential (alpha |E - E_old|^2 + beta / 2
     * tr(E - E_old)^2) / dt with the Green strains E of both steps. Its
     * derivative in F is stress() up to O(|F - F_old|^2) terms (stress()
     * uses dE = sym(dF^T F), this one (E - E_old) / dt): the line-search
     * merit of damped IPC runs, where the contact potential needs one.
     */
    double
    dissipation_potential(const dealii::Tensor<2, dim> &grad_u,
                          const dealii::Tensor<2, dim> &grad_u_old,
                          const double                  dt) const;

    /// Derivative of stress() with respect to grad_u (the current step).
    dealii::Tensor<4, dim>
    tangent(const dealii::Tensor<2, dim> &grad_u,
            const dealii::Tensor<2, dim> &grad_u_old,
            const double                  dt) const;

    /// Derivative of stress() with respect to grad_u_old (for the adjoint).
    dealii::Tensor<4, dim>
    tangent_old(const dealii::Tensor<2, dim> &grad_u,
                const dealii::Tensor<2, dim> &grad_u_old,
                const double                  dt) const;

  private:
    dealii::Tensor<4, dim>
    derivative(const dealii::Tensor<2, dim> &grad_u,
               const dealii::Tensor<2, dim> &grad_u_old,
               const double                  dt,
               const bool                    current) const;

    double alpha;
    double beta;
  };
} // namespace forma

#endif
