#include <deal.II/base/exceptions.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <forma/solvers/psd_projection.h>

#include <cmath>
#include <limits>

namespace forma
{
  using namespace dealii;

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
    // H+ = (H + |H|) / 2 with |H| = V S V^T from the SVD H = U S V^T:
    // exact for symmetric H whatever the multiplicities (LAPACK's interval
    // eigensolver fails on some contact Hessians).
    LAPACKFullMatrix<double> A(n, n);
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        A(i, j) = H(i, j);
    A.compute_svd();
    const LAPACKFullMatrix<double> &Vt = A.get_svd_vt();
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j <= i; ++j)
        {
          double a = 0;
          for (unsigned int k = 0; k < n; ++k)
            a += Vt(k, i) * A.singular_value(k) * Vt(k, j);
          H(i, j) = H(j, i) = 0.5 * (H(i, j) + a);
        }
  }
} // namespace forma
