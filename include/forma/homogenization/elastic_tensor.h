#ifndef forma_homogenization_elastic_tensor_h
#define forma_homogenization_elastic_tensor_h

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <string>

namespace forma
{
  /**
   * Tools for plane (2D) elasticity tensors, as used by homogenization.
   *
   * Voigt form: order (11, 22, 12) with engineering shear, i.e.
   * [s11, s22, s12] = C [e11, e22, 2 e12], so C(2,2) = mu for an isotropic
   * material and the isotropy conditions read C00 = C11 and
   * 2 C22 = (C00 + C11) / 2 - C01 (thesis eq. 4.9, 0-based indices).
   *
   * Isotropic moduli are the 2D ones: bulk kappa = lambda + mu, shear mu,
   * Young's modulus E = 4 kappa mu / (kappa + mu) and Poisson's ratio
   * nu = (kappa - mu) / (kappa + mu) in (-1, 1) (thesis ch. 5.2). For plane
   * stress they are the material's own E and nu; for plane strain they are
   * E / (1 - nu^2) and nu / (1 - nu).
   */
  using VoigtMatrix = dealii::Tensor<2, 3>;

  enum class PlaneModel
  {
    plane_stress,
    plane_strain
  };

  PlaneModel
  plane_model_from_string(const std::string &name);

  VoigtMatrix
  to_voigt(const dealii::SymmetricTensor<4, 2> &C);

  /// The tensor of a Voigt matrix; its symmetric part is used.
  dealii::SymmetricTensor<4, 2>
  from_voigt(const VoigtMatrix &V);

  /// The four isotropic moduli of one 2D material.
  struct IsotropicModuli
  {
    double E     = 0;
    double nu    = 0;
    double kappa = 0;
    double mu    = 0;

    static IsotropicModuli
    from_young_poisson(const double E, const double nu);
    static IsotropicModuli
    from_bulk_shear(const double kappa, const double mu);
    /// The 2D moduli of a 3D material (E, nu) in plane stress or strain.
    static IsotropicModuli
    of_material(const double E, const double nu, const PlaneModel model);

    dealii::SymmetricTensor<4, 2>
    tensor() const;
  };

  /**
   * The isotropic tensor nearest to C in the tensor (Frobenius) norm:
   * kappa = (C00 + C11 + 2 C01) / 4, mu = (C00 + C11 - 2 C01 + 4 C22) / 8.
   */
  IsotropicModuli
  isotropic_fit(const dealii::SymmetricTensor<4, 2> &C);

  /// Engineering constants of an orthotropic tensor in its current axes
  /// (from the compliance S = C^-1): E1 = 1/S00, E2 = 1/S11, G12 = 1/S22,
  /// nu12 = -S01/S00 (strain along 2 per strain along 1 under stress 1).
  struct OrthotropicModuli
  {
    double E1 = 0, E2 = 0, G12 = 0, nu12 = 0, nu21 = 0;
  };

  OrthotropicModuli
  orthotropic_moduli(const dealii::SymmetricTensor<4, 2> &C);

  struct Anisotropy
  {
    double a1 = 0; ///< |C00 - C11| / max(C00, C11)          (eq. 4.10)
    double a2 = 0; ///< |(C00 + C11)/2 - C01 - 2 C22| / max(C00, C11, C22)
    /// |C - iso(C)| / |C| in the tensor norm: also sees the shear-normal
    /// coupling terms C02, C12 that a1 and a2 ignore.
    double residual = 0;
  };

  Anisotropy
  anisotropy(const dealii::SymmetricTensor<4, 2> &C);

  /**
   * C'_ijkl = A_ip A_jq A_kr A_lt C_pqrt. With A a rotation this turns the
   * material; with A = F^-1 (F maps a reference cell onto a parallelogram
   * cell) it is the tensor that acts on the reference cell (thesis eq. 4.6),
   * and with A = F it maps back (eq. 4.7). The result's minor symmetries
   * are kept; major symmetry holds when C has it.
   */
  dealii::SymmetricTensor<4, 2>
  transform(const dealii::SymmetricTensor<4, 2> &C,
            const dealii::Tensor<2, 2>          &A);

  /// C expressed in axes rotated by `angle` (counterclockwise): the tensor
  /// of the material turned by `angle`.
  dealii::SymmetricTensor<4, 2>
  rotate(const dealii::SymmetricTensor<4, 2> &C, const double angle);

  /**
   * Exact effective tensor of a rank-one laminate: layers of `C_a` (volume
   * fraction `theta_a`) and `C_b` stacked with layers along the direction at
   * `layer_angle` from the x axis. Strain along the layers and the traction
   * on them are continuous, so the mixed (partially inverted) form of the
   * tensor averages arithmetically; this is the general form of the
   * laminate tensor of thesis eq. 5.9 (Voigt along the layers, Reuss across).
   */
  dealii::SymmetricTensor<4, 2>
  rank_one_laminate(const dealii::SymmetricTensor<4, 2> &C_a,
                    const dealii::SymmetricTensor<4, 2> &C_b,
                    const double                         theta_a,
                    const double                         layer_angle);

  /**
   * rotate(), rank_one_laminate() and IsotropicModuli::tensor() for any
   * scalar: double or a forward AD number (Sacado::Fad::DFad<double>, the
   * instantiated one), for exact derivatives of laminate tensors with
   * respect to their fraction and angle.
   */
  template <typename Number>
  dealii::SymmetricTensor<4, 2, Number>
  rotate(const dealii::SymmetricTensor<4, 2, Number> &C, const Number &angle);

  template <typename Number>
  dealii::SymmetricTensor<4, 2, Number>
  rank_one_laminate(const dealii::SymmetricTensor<4, 2, Number> &C_a,
                    const dealii::SymmetricTensor<4, 2, Number> &C_b,
                    const Number                                &theta_a,
                    const Number                                &layer_angle);

  template <typename Number>
  dealii::SymmetricTensor<4, 2, Number>
  isotropic_tensor(const Number &kappa, const Number &mu);

  /// sum_ijkl A_ijkl B_ijkl: the tensor (Frobenius) inner product.
  double
  full_contraction(const dealii::SymmetricTensor<4, 2> &A,
                   const dealii::SymmetricTensor<4, 2> &B);

  /// Smallest eigenvalue of the Voigt matrix (with engineering shear):
  /// positive iff C is positive definite.
  double
  smallest_eigenvalue(const dealii::SymmetricTensor<4, 2> &C);
} // namespace forma

#endif
