#include <deal.II/base/exceptions.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <forma/physics/material.h>

#include <cmath>

namespace forma
{
  using namespace dealii;

  ConstitutiveModel
  constitutive_model_from_string(const std::string &name)
  {
    if (name == "linear elastic")
      return ConstitutiveModel::linear_elastic;
    if (name == "neo-hookean")
      return ConstitutiveModel::neo_hookean;
    AssertThrow(false, ExcMessage("unknown material model '" + name + "'"));
    return ConstitutiveModel::linear_elastic;
  }



  MaterialProperties
  MaterialProperties::from_key_values(const std::map<std::string, double> &v,
                                      const ConstitutiveModel model,
                                      const unsigned int      dim,
                                      const std::string      &where)
  {
    static const std::vector<std::string> known = {
      "E", "nu", "lambda", "mu", "density", "damping shear", "damping bulk"};
    for (const auto &kv : v)
      AssertThrow(std::find(known.begin(), known.end(), kv.first) !=
                    known.end(),
                  ExcMessage(where + ": unknown property '" + kv.first +
                             "' (known: E, nu, lambda, mu, density, damping "
                             "shear, damping bulk)."));
    const bool by_E  = v.count("E") || v.count("nu");
    const bool by_lm = v.count("lambda") || v.count("mu");
    AssertThrow(by_E != by_lm,
                ExcMessage(where + ": give either 'E' and 'nu' or 'lambda' and "
                                   "'mu', not both and not neither."));
    MaterialProperties p;
    if (by_E)
      {
        AssertThrow(v.count("E") && v.count("nu"),
                    ExcMessage(where + ": both 'E' and 'nu' are needed."));
        p.youngs_modulus = v.at("E");
        p.poisson_ratio  = v.at("nu");
        AssertThrow(p.youngs_modulus > 0,
                    ExcMessage(where + ": Young's modulus E = " +
                               std::to_string(p.youngs_modulus) +
                               " must be positive."));
        AssertThrow(p.poisson_ratio < 0.5 && p.poisson_ratio > -1.0,
                    ExcMessage(
                      where + ": Poisson's ratio nu = " +
                      std::to_string(p.poisson_ratio) +
                      " is outside (-1, 0.5); " +
                      (model == ConstitutiveModel::linear_elastic ?
                         "linear elasticity" :
                         "the compressible Neo-Hookean law") +
                      " needs -1 < nu < 0.5 (nu = 0.5 is incompressible)."));
        const double E = p.youngs_modulus, nu = p.poisson_ratio;
        p.lambda = lame_from_young_poisson(E, nu)[0];
        p.mu     = E / (2 * (1 + nu));
      }
    else
      {
        AssertThrow(v.count("lambda") && v.count("mu"),
                    ExcMessage(where + ": both 'lambda' and 'mu' are needed."));
        p.lambda = v.at("lambda");
        p.mu     = v.at("mu");
        AssertThrow(p.mu > 0 && p.lambda + 2. * p.mu / dim > 0,
                    ExcMessage(
                      where + ": lambda = " + std::to_string(p.lambda) +
                      ", mu = " + std::to_string(p.mu) +
                      " are not admissible: need mu > 0 and a positive "
                      "bulk modulus lambda + 2 mu / dim."));
        p.youngs_modulus = p.mu * (3 * p.lambda + 2 * p.mu) / (p.lambda + p.mu);
        p.poisson_ratio  = p.lambda / (2 * (p.lambda + p.mu));
      }
    if (v.count("density"))
      p.density = v.at("density");
    if (v.count("damping shear"))
      p.damping_shear = v.at("damping shear");
    if (v.count("damping bulk"))
      p.damping_bulk = v.at("damping bulk");
    AssertThrow(p.density > 0,
                ExcMessage(where + ": density must be positive."));
    AssertThrow(p.damping_shear >= 0 && p.damping_bulk >= 0,
                ExcMessage(where + ": damping coefficients must be >= 0."));
    return p;
  }



  template <int dim>
  Material<dim>::Material(const ConstitutiveModel   model,
                          const MaterialProperties &properties,
                          const bool                plane_stress)
    : law(model)
    , props(properties)
    , plane_stress(plane_stress)
    , lambda(properties.lambda)
    , mu(properties.mu)
  {
    AssertThrow(
      !plane_stress || (dim == 2 && model == ConstitutiveModel::linear_elastic),
      ExcMessage("plane stress is available for 2D linear elasticity only."));
    if (plane_stress)
      lambda = 2. * lambda * mu / (lambda + 2. * mu);
  }



  template <int dim>
  Tensor<2, dim>
  Material<dim>::stress(const Tensor<2, dim> &grad_u) const
  {
    return first_piola_kirchhoff<dim, double>(law, grad_u, lambda, mu);
  }



  template <int dim>
  std::array<double, 2>
  Material<dim>::effective_lame(double jacobian[2][2]) const
  {
    if (jacobian)
      {
        const double l = props.lambda, m = props.mu;
        jacobian[0][0] =
          plane_stress ? 4. * m * m / ((l + 2. * m) * (l + 2. * m)) : 1.;
        jacobian[0][1] =
          plane_stress ? 2. * l * l / ((l + 2. * m) * (l + 2. * m)) : 0.;
        jacobian[1][0] = 0.;
        jacobian[1][1] = 1.;
      }
    return {{lambda, mu}};
  }



  template <int dim>
  std::array<Tensor<2, dim>, 2>
  Material<dim>::stress_lame_derivatives(const Tensor<2, dim> &grad_u) const
  {
    // d stress / d(lambda_eff, mu_eff); stress is linear in both.
    Tensor<2, dim>       d_lambda, d_mu;
    const Tensor<2, dim> I = unit_symmetric_tensor<dim>();
    if (law == ConstitutiveModel::linear_elastic)
      {
        const Tensor<2, dim> eps = 0.5 * (grad_u + transpose(grad_u));
        d_lambda                 = trace(eps) * I;
        d_mu                     = 2. * eps;
      }
    else
      {
        // The thesis (after eq. 3.25) swaps the two labels; these are the
        // derivatives of mu (F - Q) + lambda log(J) Q.
        const Tensor<2, dim> F = grad_u + I;
        const Tensor<2, dim> Q = transpose(invert(F));
        d_lambda               = std::log(determinant(F)) * Q;
        d_mu                   = F - Q;
      }
    double j[2][2];
    effective_lame(j);
    return {{j[0][0] * d_lambda + j[1][0] * d_mu,
             j[0][1] * d_lambda + j[1][1] * d_mu}};
  }



  template <int dim>
  Tensor<4, dim>
  isotropic_tangent(const double lambda, const double mu)
  {
    Tensor<4, dim> A;
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = 0; j < dim; ++j)
        {
          A[i][i][j][j] += lambda;
          A[i][j][i][j] += mu;
          A[i][j][j][i] += mu;
        }
    return A;
  }



  template <int dim>
  Tensor<4, dim>
  Material<dim>::tangent(const Tensor<2, dim> &grad_u) const
  {
    if (law == ConstitutiveModel::linear_elastic)
      return isotropic_tangent<dim>(lambda, mu);
    Tensor<4, dim>       A;
    const Tensor<2, dim> F    = grad_u + unit_symmetric_tensor<dim>();
    const Tensor<2, dim> Q    = transpose(invert(F));
    const double         logJ = std::log(determinant(F));
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = 0; j < dim; ++j)
        for (unsigned int k = 0; k < dim; ++k)
          for (unsigned int l = 0; l < dim; ++l)
            A[i][j][k][l] = (mu - lambda * logJ) * Q[i][l] * Q[k][j] +
                            lambda * Q[i][j] * Q[k][l] +
                            ((i == k && j == l) ? mu : 0.);
    return A;
  }



  template <int dim>
  double
  Material<dim>::energy_density(const Tensor<2, dim> &grad_u) const
  {
    if (law == ConstitutiveModel::linear_elastic)
      {
        const Tensor<2, dim> eps = 0.5 * (grad_u + transpose(grad_u));
        return 0.5 * lambda * trace(eps) * trace(eps) +
               mu * scalar_product(eps, eps);
      }
    const Tensor<2, dim> F    = grad_u + unit_symmetric_tensor<dim>();
    const double         logJ = std::log(determinant(F));
    return 0.5 * mu * (scalar_product(F, F) - dim) - mu * logJ +
           0.5 * lambda * logJ * logJ;
  }



  template <int dim>
  Tensor<2, dim>
  Material<dim>::cauchy_stress(const Tensor<2, dim> &grad_u) const
  {
    if (law == ConstitutiveModel::linear_elastic)
      return stress(grad_u);
    const Tensor<2, dim> F = grad_u + unit_symmetric_tensor<dim>();
    return stress(grad_u) * transpose(F) / determinant(F);
  }



  template <int dim>
  bool
  Material<dim>::admissible(const Tensor<2, dim> &grad_u) const
  {
    if (law == ConstitutiveModel::linear_elastic)
      return true;
    return determinant(grad_u + unit_symmetric_tensor<dim>()) > 0;
  }



  template <int dim>
  double
  von_mises(const Tensor<2, dim> &s)
  {
    const double trace_s = trace(s);
    double       dev2    = 0;
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = 0; j < dim; ++j)
        dev2 += s[i][j] * s[i][j];
    // |dev s|^2 in 3D embedding with s_33 = 0 for plane problems.
    dev2 -= trace_s * trace_s / 3.;
    return std::sqrt(1.5 * std::max(dev2, 0.));
  }

  std::array<double, 2>
  lame_from_young_poisson(const double E, const double nu, double jac[2][2])
  {
    const double a = (1. + nu) * (1. - 2. * nu);
    if (jac)
      {
        // d a / d nu = (1 - 2 nu) - 2 (1 + nu) = -1 - 4 nu
        jac[0][0] = nu / a;
        jac[0][1] = E * (a + nu * (1. + 4. * nu)) / (a * a);
        jac[1][0] = 1. / (2. * (1. + nu));
        jac[1][1] = -E / (2. * (1. + nu) * (1. + nu));
      }
    return {{E * nu / a, E / (2. * (1. + nu))}};
  }

  template class Material<2>;
  template class Material<3>;
  template Tensor<4, 2>
  isotropic_tangent<2>(const double, const double);
  template Tensor<4, 3>
  isotropic_tangent<3>(const double, const double);
  template double
  von_mises<2>(const Tensor<2, 2> &);
  template double
  von_mises<3>(const Tensor<2, 3> &);
} // namespace forma
