// project_to_psd (Eigen's self-adjoint eigensolver, fixed sizes for the IPC
// and quad-mesh Hessians) against an independent computation: H+ =
// (H + |H|) / 2 with |H| from LAPACK's SVD, on pseudo-random symmetric
// matrices of every dispatched size and one dynamic size, a matrix with
// repeated negative eigenvalues, a PSD matrix (untouched), and a matrix with
// a non-finite entry (a message naming the caller).

#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <forma/solvers/psd_projection.h>

#include "../tests.h"

#include <cmath>
#include <cstdint>
#include <limits>

using namespace dealii;

namespace
{
  /// Reproducible numbers in [-1, 1).
  double
  next(std::uint64_t &state)
  {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return 2. * ((state >> 11) * (1. / 9007199254740992.)) - 1.;
  }

  FullMatrix<double>
  random_symmetric(const unsigned int n, std::uint64_t &state)
  {
    FullMatrix<double> H(n, n);
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j <= i; ++j)
        H(i, j) = H(j, i) = next(state);
    return H;
  }

  /// (H + |H|) / 2 from the SVD H = U S V^T (|H| = V S V^T).
  FullMatrix<double>
  reference(const FullMatrix<double> &H)
  {
    const unsigned int       n = H.m();
    LAPACKFullMatrix<double> A(n, n);
    A = H;
    A.compute_svd();
    const LAPACKFullMatrix<double> &Vt = A.get_svd_vt();
    FullMatrix<double>              R(n, n);
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = 0; j < n; ++j)
        {
          double a = 0;
          for (unsigned int k = 0; k < n; ++k)
            a += Vt(k, i) * A.singular_value(k) * Vt(k, j);
          R(i, j) = 0.5 * (H(i, j) + a);
        }
    return R;
  }

  double
  lowest_eigenvalue(const FullMatrix<double> &H)
  {
    LAPACKFullMatrix<double> A(H.m(), H.m());
    A = H;
    A.compute_eigenvalues();
    double lowest = std::numeric_limits<double>::max();
    for (unsigned int i = 0; i < H.m(); ++i)
      lowest = std::min(lowest, A.eigenvalue(i).real());
    return lowest;
  }

  void
  check(const std::string &name, const FullMatrix<double> &H)
  {
    FullMatrix<double> P = H;
    forma::project_to_psd(P, name);
    FullMatrix<double> difference = reference(H);
    difference.add(-1., P);
    const double scale = H.frobenius_norm();
    deallog << name << " (" << H.m() << "x" << H.m()
            << "): lowest eigenvalue before "
            << (lowest_eigenvalue(H) < 0 ? "negative" : "non-negative")
            << ", after >= -1e-13 |H|: "
            << (lowest_eigenvalue(P) >= -1e-13 * scale ? "yes" : "no")
            << ", equal to the SVD projection to 1e-13 |H|: "
            << (difference.frobenius_norm() <= 1e-13 * scale ? "yes" : "no")
            << std::endl;
  }
} // namespace

int
main()
{
  initlog();
  std::uint64_t state = 11;
  for (const unsigned int n : {4u, 6u, 8u, 9u, 12u, 15u})
    check("random", random_symmetric(n, state));

  // Eigenvalues -2, -2, -2, 1, 1, 3 in a rotated basis (Q = I - 2 v v^T).
  FullMatrix<double>  D(6, 6), Q(6, 6), H(6, 6), T(6, 6);
  const double        lambda[6] = {-2, -2, -2, 1, 1, 3};
  std::vector<double> v(6);
  double              norm = 0;
  for (auto &x : v)
    norm += (x = next(state)) * x;
  for (unsigned int i = 0; i < 6; ++i)
    {
      D(i, i) = lambda[i];
      for (unsigned int j = 0; j < 6; ++j)
        Q(i, j) = (i == j) - 2. * v[i] * v[j] / norm;
    }
  Q.mmult(T, D);
  T.mTmult(H, Q);
  check("repeated", H);

  // PSD: returned as it came, to round-off.
  FullMatrix<double> S = random_symmetric(6, state), SPD(6, 6);
  S.Tmmult(SPD, S);
  FullMatrix<double> P = SPD;
  forma::project_to_psd(P, "psd");
  P.add(-1., SPD);
  deallog << "PSD input unchanged: "
          << (P.frobenius_norm() <= 1e-13 * SPD.frobenius_norm() ? "yes" : "no")
          << std::endl;

  FullMatrix<double> bad = random_symmetric(4, state);
  bad(1, 2)              = std::numeric_limits<double>::quiet_NaN();
  try
    {
      forma::project_to_psd(bad, "IPC contact");
      deallog << "non-finite entry: no error" << std::endl;
    }
  catch (const ExceptionBase &e)
    {
      const bool named =
        std::string(e.what()).find("IPC contact: a Hessian is not finite") !=
        std::string::npos;
      deallog << "non-finite entry: error naming the caller: "
              << (named ? "yes" : "no") << std::endl;
    }
}
