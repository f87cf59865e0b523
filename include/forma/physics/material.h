#ifndef forma_physics_material_h
#define forma_physics_material_h

#include <deal.II/base/tensor.h>

#include <array>
#include <cmath>
#include <map>
#include <string>

namespace forma
{
  enum class ConstitutiveModel
  {
    linear_elastic, ///< small strain, sigma = C : eps(grad u)
    neo_hookean     ///< compressible, thesis ch. 3.7.2 (after eq. 3.25)
  };

  ConstitutiveModel
  constitutive_model_from_string(const std::string &name);

  /// Per-body constants; (E, nu) and (lambda, mu) are both always filled.
  struct MaterialProperties
  {
    double youngs_modulus = 0;
    double poisson_ratio  = 0;
    double lambda         = 0;
    double mu             = 0;
    double density        = 1;
    double damping_shear  = 0; ///< alpha of Brown et al. damping (Pa s)
    double damping_bulk   = 0; ///< beta of Brown et al. damping (Pa s)

    /**
     * From `E=..., nu=...` or `lambda=..., mu=...` plus optional `density`,
     * `damping shear`, `damping bulk`. Checks admissibility for `model` and
     * names `where` (e.g. "Material/Bodies, material id 1") in errors.
     */
    static MaterialProperties
    from_key_values(const std::map<std::string, double> &values,
                    const ConstitutiveModel              model,
                    const unsigned int                   dim,
                    const std::string                   &where);
  };

  /**
   * First Piola-Kirchhoff stress f(grad u; lambda, mu) of thesis ch. 3.7.2,
   * generic in the number type so objectives can differentiate it with
   * Sacado. lambda is the effective value (plane stress already applied).
   */
  template <int dim, typename Number>
  dealii::Tensor<2, dim, Number>
  first_piola_kirchhoff(const ConstitutiveModel               law,
                        const dealii::Tensor<2, dim, Number> &grad_u,
                        const Number                         &lambda,
                        const Number                         &mu)
  {
    // Scalars are materialized before scaling tensors: AD numbers with
    // expression templates (Sacado) do not multiply tensors as expressions.
    using std::log;
    dealii::Tensor<2, dim, Number> I;
    for (unsigned int d = 0; d < dim; ++d)
      I[d][d] = 1.;
    if (law == ConstitutiveModel::linear_elastic)
      {
        const Number                         half = 0.5;
        const dealii::Tensor<2, dim, Number> eps =
          half * (grad_u + transpose(grad_u));
        const Number a      = lambda * trace(eps);
        const Number two_mu = 2. * mu;
        return a * I + two_mu * eps;
      }
    const dealii::Tensor<2, dim, Number> F = grad_u + I;
    const dealii::Tensor<2, dim, Number> Q = transpose(invert(F));
    const Number lambda_log_J              = lambda * log(determinant(F));
    return mu * (F - Q) + lambda_log_J * Q;
  }

  /// lambda = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu)) and the
  /// Jacobian d(lambda, mu)/d(E, nu) (row: lambda, mu; column: E, nu).
  std::array<double, 2>
  lame_from_young_poisson(const double E,
                          const double nu,
                          double       jacobian[2][2] = nullptr);

  /// lambda I x I + mu (d_ik d_jl + d_il d_jk): the tangent of linear
  /// isotropic elasticity (and of Neo-Hookean at F = I).
  template <int dim>
  dealii::Tensor<4, dim>
  isotropic_tangent(const double lambda, const double mu);

  /**
   * Stress laws in the form used by every forma force (thesis eq. 3.23):
   * stress(grad u) is the first Piola-Kirchhoff stress (equal to the Cauchy
   * stress for linear elasticity), tangent() its derivative with respect to
   * grad u (nabla_1 f in eq. 3.25). In 2D, linear elasticity is plane strain
   * or plane stress (the latter through the reduced lambda); Neo-Hookean is
   * plane strain.
   */
  template <int dim>
  class Material
  {
  public:
    Material(const ConstitutiveModel   model,
             const MaterialProperties &properties,
             const bool                plane_stress = false);

    dealii::Tensor<2, dim>
    stress(const dealii::Tensor<2, dim> &grad_u) const;

    dealii::Tensor<4, dim>
    tangent(const dealii::Tensor<2, dim> &grad_u) const;

    double
    energy_density(const dealii::Tensor<2, dim> &grad_u) const;

    /// Cauchy stress (true stress in the deformed configuration).
    dealii::Tensor<2, dim>
    cauchy_stress(const dealii::Tensor<2, dim> &grad_u) const;

    /**
     * Derivatives of stress() with respect to the Lame parameters given in
     * the properties (before the plane-stress reduction): [d/dlambda,
     * d/dmu].
     */
    std::array<dealii::Tensor<2, dim>, 2>
    stress_lame_derivatives(const dealii::Tensor<2, dim> &grad_u) const;

    /// Effective (lambda, mu) used in the stress and d(effective)/d(input),
    /// rows lambda_eff, mu_eff; columns lambda, mu.
    std::array<double, 2>
    effective_lame(double jacobian[2][2] = nullptr) const;

    /// False where the deformation inverts the material (det F <= 0).
    bool
    admissible(const dealii::Tensor<2, dim> &grad_u) const;

    ConstitutiveModel
    model() const
    {
      return law;
    }

    const MaterialProperties &
    properties() const
    {
      return props;
    }

  private:
    ConstitutiveModel  law;
    MaterialProperties props;
    bool               plane_stress;
    double             lambda; ///< effective (plane stress reduces it)
    double             mu;
  };

  /// von Mises equivalent of a stress tensor (plane problems: the in-plane
  /// tensor, out-of-plane components taken as zero).
  template <int dim>
  double
  von_mises(const dealii::Tensor<2, dim> &sigma);
} // namespace forma

#endif
