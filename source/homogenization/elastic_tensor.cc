#include <deal.II/base/exceptions.h>
#include <deal.II/base/tensor.h>
#include <deal.II/differentiation/ad/sacado_product_types.h>

#include <forma/homogenization/elastic_tensor.h>

#include <Sacado.hpp>

#include <algorithm>
#include <cmath>

namespace forma
{
  using namespace dealii;

  namespace
  {
    // Voigt index -> tensor indices (i, j).
    constexpr unsigned int voigt_i[3] = {0, 1, 0};
    constexpr unsigned int voigt_j[3] = {0, 1, 1};

    template <typename Number>
    Tensor<2, 3, Number>
    voigt_of(const SymmetricTensor<4, 2, Number> &C)
    {
      // With engineering shear the Voigt entries are the tensor entries.
      Tensor<2, 3, Number> V;
      for (unsigned int a = 0; a < 3; ++a)
        for (unsigned int b = 0; b < 3; ++b)
          V[a][b] = C[voigt_i[a]][voigt_j[a]][voigt_i[b]][voigt_j[b]];
      return V;
    }

    template <typename Number>
    SymmetricTensor<4, 2, Number>
    tensor_of(const Tensor<2, 3, Number> &V)
    {
      SymmetricTensor<4, 2, Number> C;
      for (unsigned int a = 0; a < 3; ++a)
        for (unsigned int b = 0; b < 3; ++b)
          C[voigt_i[a]][voigt_j[a]][voigt_i[b]][voigt_j[b]] =
            0.5 * (V[a][b] + V[b][a]);
      return C;
    }

    template <typename Number, typename MatrixNumber>
    SymmetricTensor<4, 2, Number>
    transformed(const SymmetricTensor<4, 2, Number> &C,
                const Tensor<2, 2, MatrixNumber>    &A)
    {
      SymmetricTensor<4, 2, Number> result;
      for (unsigned int i = 0; i < 2; ++i)
        for (unsigned int j = i; j < 2; ++j)
          for (unsigned int k = 0; k < 2; ++k)
            for (unsigned int l = k; l < 2; ++l)
              {
                Number sum = 0;
                for (unsigned int p = 0; p < 2; ++p)
                  for (unsigned int q = 0; q < 2; ++q)
                    for (unsigned int r = 0; r < 2; ++r)
                      for (unsigned int t = 0; t < 2; ++t)
                        sum +=
                          A[i][p] * A[j][q] * A[k][r] * A[l][t] * C[p][q][r][t];
                result[i][j][k][l] = sum;
              }
      return result;
    }

    // The mixed form of C in the layer frame (layers along x): the entries
    // continuous across the layers (e11, s22, s12) against the jumping ones
    // (s11, e22, 2 e12). Voigt index 0 = "t", {1, 2} = "n".
    template <typename Number>
    Tensor<2, 3, Number>
    mixed_form(const Tensor<2, 3, Number> &V)
    {
      Tensor<2, 2, Number> nn;
      for (unsigned int a = 0; a < 2; ++a)
        for (unsigned int b = 0; b < 2; ++b)
          nn[a][b] = V[a + 1][b + 1];
      const Tensor<2, 2, Number> nn_inv = invert(nn);
      Tensor<2, 3, Number>       M;
      Number                     tn_nn_nt = 0;
      for (unsigned int a = 0; a < 2; ++a)
        for (unsigned int b = 0; b < 2; ++b)
          {
            tn_nn_nt += V[0][a + 1] * nn_inv[a][b] * V[b + 1][0];
            M[0][a + 1] += V[0][b + 1] * nn_inv[b][a];
            M[a + 1][0] -= nn_inv[a][b] * V[b + 1][0];
            M[a + 1][b + 1] = nn_inv[a][b];
          }
      M[0][0] = V[0][0] - tn_nn_nt;
      return M;
    }

    // The inverse of mixed_form().
    template <typename Number>
    Tensor<2, 3, Number>
    unmixed_form(const Tensor<2, 3, Number> &M)
    {
      Tensor<2, 2, Number> nn_inv;
      for (unsigned int a = 0; a < 2; ++a)
        for (unsigned int b = 0; b < 2; ++b)
          nn_inv[a][b] = M[a + 1][b + 1];
      const Tensor<2, 2, Number> nn = invert(nn_inv);
      Tensor<2, 3, Number>       V;
      for (unsigned int a = 0; a < 2; ++a)
        for (unsigned int b = 0; b < 2; ++b)
          {
            V[a + 1][b + 1] = nn[a][b];
            V[a + 1][0] -= nn[a][b] * M[b + 1][0];
            V[0][a + 1] += M[0][b + 1] * nn[b][a];
          }
      // C_tt = M_tt + C_tn C_nn^-1 C_nt
      V[0][0] = M[0][0];
      for (unsigned int a = 0; a < 2; ++a)
        for (unsigned int b = 0; b < 2; ++b)
          V[0][0] += V[0][a + 1] * M[a + 1][b + 1] * V[b + 1][0];
      return V;
    }
  } // namespace



  PlaneModel
  plane_model_from_string(const std::string &name)
  {
    if (name == "plane stress")
      return PlaneModel::plane_stress;
    if (name == "plane strain")
      return PlaneModel::plane_strain;
    AssertThrow(false,
                ExcMessage("unknown plane model '" + name +
                           "' (plane stress | plane strain)"));
    return PlaneModel::plane_stress;
  }



  VoigtMatrix
  to_voigt(const SymmetricTensor<4, 2> &C)
  {
    return voigt_of(C);
  }



  SymmetricTensor<4, 2>
  from_voigt(const VoigtMatrix &V)
  {
    return tensor_of(V);
  }



  IsotropicModuli
  IsotropicModuli::from_young_poisson(const double E, const double nu)
  {
    AssertThrow(E > 0 && nu > -1 && nu < 1,
                ExcMessage("2D moduli need E > 0 and -1 < nu < 1 (got E = " +
                           std::to_string(E) + ", nu = " + std::to_string(nu) +
                           ")"));
    IsotropicModuli m;
    m.E     = E;
    m.nu    = nu;
    m.kappa = E / (2 * (1 - nu));
    m.mu    = E / (2 * (1 + nu));
    return m;
  }



  IsotropicModuli
  IsotropicModuli::from_bulk_shear(const double kappa, const double mu)
  {
    IsotropicModuli m;
    m.kappa = kappa;
    m.mu    = mu;
    m.E     = (kappa + mu != 0) ? 4 * kappa * mu / (kappa + mu) : 0;
    m.nu    = (kappa + mu != 0) ? (kappa - mu) / (kappa + mu) : 0;
    return m;
  }



  IsotropicModuli
  IsotropicModuli::of_material(const double     E,
                               const double     nu,
                               const PlaneModel model)
  {
    AssertThrow(E > 0 && nu > -1 && nu < 0.5,
                ExcMessage("a base material needs E > 0 and -1 < nu < 0.5 "
                           "(got E = " +
                           std::to_string(E) + ", nu = " + std::to_string(nu) +
                           ")"));
    if (model == PlaneModel::plane_stress)
      return from_young_poisson(E, nu);
    return from_young_poisson(E / (1 - nu * nu), nu / (1 - nu));
  }



  SymmetricTensor<4, 2>
  IsotropicModuli::tensor() const
  {
    return isotropic_tensor(kappa, mu);
  }



  template <typename Number>
  SymmetricTensor<4, 2, Number>
  isotropic_tensor(const Number &kappa, const Number &mu)
  {
    // kappa I x I + 2 mu (I_sym - I x I / 2), i.e. lambda = kappa - mu.
    SymmetricTensor<4, 2, Number> C;
    for (unsigned int i = 0; i < 2; ++i)
      {
        C[i][i][i][i]         = kappa + mu;
        C[i][i][1 - i][1 - i] = kappa - mu;
      }
    C[0][1][0][1] = mu;
    return C;
  }



  IsotropicModuli
  isotropic_fit(const SymmetricTensor<4, 2> &C)
  {
    const VoigtMatrix V = to_voigt(C);
    return IsotropicModuli::from_bulk_shear(
      (V[0][0] + V[1][1] + 2 * V[0][1]) / 4,
      (V[0][0] + V[1][1] - 2 * V[0][1] + 4 * V[2][2]) / 8);
  }



  Anisotropy
  anisotropy(const SymmetricTensor<4, 2> &C)
  {
    const VoigtMatrix V = to_voigt(C);
    Anisotropy        a;
    a.a1 = std::abs(V[0][0] - V[1][1]) / std::max(V[0][0], V[1][1]);
    a.a2 = std::abs((V[0][0] + V[1][1]) / 2 - V[0][1] - 2 * V[2][2]) /
           std::max({V[0][0], V[1][1], V[2][2]});
    const double norm = C.norm();
    a.residual = norm > 0 ? (C - isotropic_fit(C).tensor()).norm() / norm : 0;
    return a;
  }



  OrthotropicModuli
  orthotropic_moduli(const SymmetricTensor<4, 2> &C)
  {
    AssertThrow(smallest_eigenvalue(C) > 0,
                ExcMessage("orthotropic moduli of a tensor that is not "
                           "positive definite"));
    const VoigtMatrix S = invert(to_voigt(C));
    OrthotropicModuli m;
    m.E1   = 1 / S[0][0];
    m.E2   = 1 / S[1][1];
    m.G12  = 1 / S[2][2];
    m.nu12 = -S[0][1] / S[0][0];
    m.nu21 = -S[0][1] / S[1][1];
    return m;
  }



  SymmetricTensor<4, 2>
  transform(const SymmetricTensor<4, 2> &C, const Tensor<2, 2> &A)
  {
    return transformed(C, A);
  }



  SymmetricTensor<4, 2>
  rotate(const SymmetricTensor<4, 2> &C, const double angle)
  {
    return rotate<double>(C, angle);
  }



  template <typename Number>
  SymmetricTensor<4, 2, Number>
  rotate(const SymmetricTensor<4, 2, Number> &C, const Number &angle)
  {
    using std::cos;
    using std::sin;
    const Number         c = cos(angle), s = sin(angle);
    Tensor<2, 2, Number> A;
    A[0][0] = c;
    A[0][1] = -s;
    A[1][0] = s;
    A[1][1] = c;
    return transformed(C, A);
  }



  SymmetricTensor<4, 2>
  rank_one_laminate(const SymmetricTensor<4, 2> &C_a,
                    const SymmetricTensor<4, 2> &C_b,
                    const double                 theta_a,
                    const double                 layer_angle)
  {
    return rank_one_laminate<double>(C_a, C_b, theta_a, layer_angle);
  }



  template <typename Number>
  SymmetricTensor<4, 2, Number>
  rank_one_laminate(const SymmetricTensor<4, 2, Number> &C_a,
                    const SymmetricTensor<4, 2, Number> &C_b,
                    const Number                        &theta_a,
                    const Number                        &layer_angle)
  {
    const double theta = Sacado::ScalarValue<Number>::eval(theta_a);
    AssertThrow(theta >= 0 && theta <= 1,
                ExcMessage("laminate volume fraction " + std::to_string(theta) +
                           " is outside [0, 1]"));
    // Strain along the layers and the traction on them are continuous, so
    // the mixed forms of the layers average arithmetically.
    const Number         minus_angle = -layer_angle;
    Tensor<2, 3, Number> M = mixed_form(voigt_of(rotate(C_a, minus_angle)));
    const Number         theta_b = 1. - theta_a;
    M *= theta_a;
    M += theta_b * mixed_form(voigt_of(rotate(C_b, minus_angle)));
    return rotate(tensor_of(unmixed_form(M)), layer_angle);
  }



  template SymmetricTensor<4, 2, double>
  isotropic_tensor(const double &, const double &);
  template SymmetricTensor<4, 2, Sacado::Fad::DFad<double>>
  isotropic_tensor(const Sacado::Fad::DFad<double> &,
                   const Sacado::Fad::DFad<double> &);
  template SymmetricTensor<4, 2, Sacado::Fad::DFad<double>>
  rotate(const SymmetricTensor<4, 2, Sacado::Fad::DFad<double>> &,
         const Sacado::Fad::DFad<double> &);
  template SymmetricTensor<4, 2, Sacado::Fad::DFad<double>>
  rank_one_laminate(const SymmetricTensor<4, 2, Sacado::Fad::DFad<double>> &,
                    const SymmetricTensor<4, 2, Sacado::Fad::DFad<double>> &,
                    const Sacado::Fad::DFad<double> &,
                    const Sacado::Fad::DFad<double> &);



  double
  full_contraction(const SymmetricTensor<4, 2> &A,
                   const SymmetricTensor<4, 2> &B)
  {
    double sum = 0;
    for (unsigned int i = 0; i < 2; ++i)
      for (unsigned int j = 0; j < 2; ++j)
        for (unsigned int k = 0; k < 2; ++k)
          for (unsigned int l = 0; l < 2; ++l)
            sum += A[i][j][k][l] * B[i][j][k][l];
    return sum;
  }



  double
  smallest_eigenvalue(const SymmetricTensor<4, 2> &C)
  {
    const VoigtMatrix     V = to_voigt(C);
    SymmetricTensor<2, 3> S;
    for (unsigned int a = 0; a < 3; ++a)
      for (unsigned int b = a; b < 3; ++b)
        S[a][b] = 0.5 * (V[a][b] + V[b][a]);
    return eigenvalues(S)[2];
  }
} // namespace forma
