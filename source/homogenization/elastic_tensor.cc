#include <deal.II/base/exceptions.h>
#include <deal.II/lac/full_matrix.h>

#include <forma/homogenization/elastic_tensor.h>

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
    // With engineering shear the Voigt entries are the tensor entries.
    VoigtMatrix V;
    for (unsigned int a = 0; a < 3; ++a)
      for (unsigned int b = 0; b < 3; ++b)
        V[a][b] = C[voigt_i[a]][voigt_j[a]][voigt_i[b]][voigt_j[b]];
    return V;
  }



  SymmetricTensor<4, 2>
  from_voigt(const VoigtMatrix &V)
  {
    SymmetricTensor<4, 2> C;
    for (unsigned int a = 0; a < 3; ++a)
      for (unsigned int b = 0; b < 3; ++b)
        C[voigt_i[a]][voigt_j[a]][voigt_i[b]][voigt_j[b]] =
          0.5 * (V[a][b] + V[b][a]);
    return C;
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
    // kappa I x I + 2 mu (I_sym - I x I / 2), i.e. lambda = kappa - mu.
    const SymmetricTensor<2, 2> I = unit_symmetric_tensor<2>();
    return (kappa - mu) * outer_product(I, I) + 2 * mu * identity_tensor<2>();
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
    SymmetricTensor<4, 2> result;
    for (unsigned int i = 0; i < 2; ++i)
      for (unsigned int j = i; j < 2; ++j)
        for (unsigned int k = 0; k < 2; ++k)
          for (unsigned int l = k; l < 2; ++l)
            {
              double sum = 0;
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



  SymmetricTensor<4, 2>
  rotate(const SymmetricTensor<4, 2> &C, const double angle)
  {
    const double c = std::cos(angle), s = std::sin(angle);
    return transform(C, Tensor<2, 2>({{c, -s}, {s, c}}));
  }



  SymmetricTensor<4, 2>
  rank_one_laminate(const SymmetricTensor<4, 2> &C_a,
                    const SymmetricTensor<4, 2> &C_b,
                    const double                 theta_a,
                    const double                 layer_angle)
  {
    AssertThrow(theta_a >= 0 && theta_a <= 1,
                ExcMessage("laminate volume fraction " +
                           std::to_string(theta_a) + " is outside [0, 1]"));
    // In the layer frame (layers along x): e11 and (s22, s12) are continuous,
    // e22, 2 e12 and s11 jump. Voigt index 0 = "t", {1, 2} = "n".
    auto mixed = [&](const SymmetricTensor<4, 2> &C) {
      const VoigtMatrix  V = to_voigt(rotate(C, -layer_angle));
      FullMatrix<double> nn(2, 2), nn_inv(2, 2);
      for (unsigned int a = 0; a < 2; ++a)
        for (unsigned int b = 0; b < 2; ++b)
          nn(a, b) = V[a + 1][b + 1];
      nn_inv.invert(nn);
      FullMatrix<double> M(3, 3);
      double             tn_nn_nt = 0;
      for (unsigned int a = 0; a < 2; ++a)
        for (unsigned int b = 0; b < 2; ++b)
          {
            tn_nn_nt += V[0][a + 1] * nn_inv(a, b) * V[b + 1][0];
            M(0, a + 1) += V[0][b + 1] * nn_inv(b, a);
            M(a + 1, 0) -= nn_inv(a, b) * V[b + 1][0];
            M(a + 1, b + 1) = nn_inv(a, b);
          }
      M(0, 0) = V[0][0] - tn_nn_nt;
      return M;
    };
    FullMatrix<double> M = mixed(C_a);
    M *= theta_a;
    M.add(1 - theta_a, mixed(C_b));

    FullMatrix<double> nn_inv(2, 2), nn(2, 2);
    for (unsigned int a = 0; a < 2; ++a)
      for (unsigned int b = 0; b < 2; ++b)
        nn_inv(a, b) = M(a + 1, b + 1);
    nn.invert(nn_inv);
    VoigtMatrix V;
    for (unsigned int a = 0; a < 2; ++a)
      for (unsigned int b = 0; b < 2; ++b)
        {
          V[a + 1][b + 1] = nn(a, b);
          V[a + 1][0] -= nn(a, b) * M(b + 1, 0);
          V[0][a + 1] += M(0, b + 1) * nn(b, a);
        }
    // C_tt = M_tt + C_tn C_nn^-1 C_nt
    V[0][0] = M(0, 0);
    for (unsigned int a = 0; a < 2; ++a)
      for (unsigned int b = 0; b < 2; ++b)
        V[0][0] += V[0][a + 1] * M(a + 1, b + 1) * V[b + 1][0];
    return rotate(from_voigt(V), layer_angle);
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
