#ifndef forma_adjoint_auto_diff_term_h
#define forma_adjoint_auto_diff_term_h

#include <deal.II/differentiation/ad/sacado_math.h>
#include <deal.II/differentiation/ad/sacado_number_types.h>
#include <deal.II/differentiation/ad/sacado_product_types.h>

#include <forma/adjoint/objective.h>

#include <Sacado.hpp>

#include <limits>

namespace forma
{
  /// The keys x, y[, z] of a record as a vector; `fallback` for a missing
  /// key (NaN: the keys are required).
  template <int dim>
  dealii::Tensor<1, dim>
  axis_keys(const KeyValueRecord &r,
            const double fallback = std::numeric_limits<double>::quiet_NaN())
  {
    const char            *axes[3] = {"x", "y", "z"};
    dealii::Tensor<1, dim> v;
    for (unsigned int d = 0; d < dim; ++d)
      v[d] = r.key(axes[d], fallback);
    return v;
  }

  /**
   * Terms state their integrand once, generic in the number type; the
   * partials come from forward-mode AD over (x, u, grad u, lambda, mu).
   * `Derived` provides
   *   template <typename N> N j(unsigned int k, const IntegrandContext<dim> &,
   *     const Tensor<1, dim, N> &x, const Tensor<1, dim, N> &u,
   *     const Tensor<2, dim, N> &grad_u, const N &lambda, const N &mu) const;
   * A term that overrides integrals() restricts them to `materials` or
   * overrides restrictable() to refuse the `material` key.
   */
  template <int dim, typename Derived>
  class AutoDiffTerm : public ObjectiveTerm<dim>
  {
  public:
    using ObjectiveTerm<dim>::ObjectiveTerm;

    // Default: one volume integral (over `materials`, empty: all),
    // J = I.
    std::vector<typename ObjectiveTerm<dim>::Integral>
    integrals() const override
    {
      typename ObjectiveTerm<dim>::Integral i;
      i.material_ids = materials;
      return {i};
    }

    bool
    restrictable() const override
    {
      return true;
    }

    void
    restrict_to_material(const dealii::types::material_id id) override
    {
      materials = {id};
    }

    std::set<dealii::types::material_id> materials;

    double
    combine(const std::vector<double> &I,
            std::vector<double>       *grad) const override
    {
      if (grad)
        *grad = {1.};
      return I[0];
    }

    void
    integrand(const unsigned int            k,
              const IntegrandContext<dim>  &c,
              const dealii::Tensor<1, dim> &x,
              const dealii::Tensor<1, dim> &u,
              const dealii::Tensor<2, dim> &grad_u,
              const double                  lambda,
              const double                  mu,
              const bool                    derivatives,
              IntegrandValue<dim>          &r) const override
    {
      const auto &self = static_cast<const Derived &>(*this);
      if (!derivatives)
        {
          r.value = self.template j<double>(k, c, x, u, grad_u, lambda, mu);
          return;
        }
      constexpr int n = 2 * dim + dim * dim + 2;
      using AD = Sacado::Fad::DFad<double>; // what deal.II tensors support
      dealii::Tensor<1, dim, AD> xa, ua;
      dealii::Tensor<2, dim, AD> ga;
      int                        i = 0;
      for (unsigned int d = 0; d < dim; ++d)
        xa[d] = AD(n, i++, x[d]);
      for (unsigned int d = 0; d < dim; ++d)
        ua[d] = AD(n, i++, u[d]);
      for (unsigned int d = 0; d < dim; ++d)
        for (unsigned int e = 0; e < dim; ++e)
          ga[d][e] = AD(n, i++, grad_u[d][e]);
      const AD la(n, i++, lambda);
      const AD ma(n, i++, mu);
      const AD v = self.template j<AD>(k, c, xa, ua, ga, la, ma);
      r.value    = v.val();
      i          = 0;
      for (unsigned int d = 0; d < dim; ++d)
        r.d_x[d] = v.dx(i++);
      for (unsigned int d = 0; d < dim; ++d)
        r.d_u[d] = v.dx(i++);
      for (unsigned int d = 0; d < dim; ++d)
        for (unsigned int e = 0; e < dim; ++e)
          r.d_grad_u[d][e] = v.dx(i++);
      r.d_lambda = v.dx(i++);
      r.d_mu     = v.dx(i++);
    }
  };

  /// The stress f(grad u) of the forces, with the plane-stress reduction.
  template <int dim, typename Number>
  dealii::Tensor<2, dim, Number>
  integrand_stress(const IntegrandContext<dim>          &c,
                   const dealii::Tensor<2, dim, Number> &grad_u,
                   const Number                         &lambda,
                   const Number                         &mu)
  {
    const Number l =
      c.plane_stress ? Number(2. * lambda * mu / (lambda + 2. * mu)) : lambda;
    return first_piola_kirchhoff<dim, Number>(c.model, grad_u, l, mu);
  }

  /// Squared stress measure: Frobenius, or von Mises (plane problems embed
  /// the in-plane tensor with zero out-of-plane components).
  template <int dim, typename Number>
  Number
  stress_measure_squared(const dealii::Tensor<2, dim, Number> &s,
                         const bool                            von_mises)
  {
    Number ss = 0, tr = 0;
    for (unsigned int i = 0; i < dim; ++i)
      {
        tr += s[i][i];
        for (unsigned int j = 0; j < dim; ++j)
          ss += s[i][j] * s[i][j];
      }
    return von_mises ? Number(1.5) * (ss - tr * tr / Number(3.)) : ss;
  }

  /// The penalty phi(z) = max(z, 0)^2 of thesis eq. 3.41.
  template <typename Number>
  Number
  positive_part_squared(const Number &z)
  {
    return z > 0 ? z * z : Number(0.);
  }
} // namespace forma

#endif
