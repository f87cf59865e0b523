#include <deal.II/base/exceptions.h>
#include <deal.II/lac/full_matrix.h>

#include <forma/solvers/psd_projection.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>

namespace forma
{
  using namespace dealii;

  namespace
  {
    /// H <- V max(Lambda, 0) V^T from Eigen's self-adjoint eigensolver
    /// (Householder tridiagonalization and implicit QR: robust for
    /// repeated eigenvalues, no heap for fixed N).
    template <int N>
    void
    clip_negative_eigenvalues(FullMatrix<double> &H, const std::string &what)
    {
      using Matrix         = Eigen::Matrix<double, N, N>;
      const Eigen::Index n = H.m();
      Matrix             A(n, n);
      for (Eigen::Index i = 0; i < n; ++i)
        for (Eigen::Index j = 0; j < n; ++j)
          A(i, j) = H(i, j);
      const Eigen::SelfAdjointEigenSolver<Matrix> eigen(A);
      AssertThrow(eigen.info() == Eigen::Success,
                  ExcMessage(what + ": the eigensolver failed on a Hessian."));
      const Matrix &V = eigen.eigenvectors();
      A = V * eigen.eigenvalues().cwiseMax(0.).asDiagonal() * V.transpose();
      for (Eigen::Index i = 0; i < n; ++i)
        for (Eigen::Index j = 0; j <= i; ++j)
          H(i, j) = H(j, i) = 0.5 * (A(i, j) + A(j, i));
    }
  } // namespace



  void
  project_to_psd(FullMatrix<double> &H, const std::string &what)
  {
    const unsigned int n = H.m();
    // Symmetrize; by Gershgorin's bound most Hessians have no negative
    // eigenvalue: nothing to do then.
    double lowest = std::numeric_limits<double>::max();
    for (unsigned int i = 0; i < n; ++i)
      {
        double radius = 0;
        for (unsigned int j = 0; j < n; ++j)
          {
            H(i, j) = H(j, i) = 0.5 * (H(i, j) + H(j, i));
            AssertThrow(std::isfinite(H(i, j)),
                        ExcMessage(what + ": a Hessian is not finite."));
            if (j != i)
              radius += std::abs(H(i, j));
          }
        lowest = std::min(lowest, H(i, i) - radius);
      }
    if (lowest >= 0)
      return;
    switch (n)
      {
        // The pair and element sizes of IPC (2D: 4, 6; 3D: 6, 9, 12) and
        // of quad mesh optimization (8): fixed-size, on the stack.
        case 4:
          clip_negative_eigenvalues<4>(H, what);
          break;
        case 6:
          clip_negative_eigenvalues<6>(H, what);
          break;
        case 8:
          clip_negative_eigenvalues<8>(H, what);
          break;
        case 9:
          clip_negative_eigenvalues<9>(H, what);
          break;
        case 12:
          clip_negative_eigenvalues<12>(H, what);
          break;
        default:
          clip_negative_eigenvalues<Eigen::Dynamic>(H, what);
      }
  }
} // namespace forma
