// Time per call of project_to_psd (Eigen, fixed size) against the LAPACK SVD
// it replaced, on pseudo-random symmetric pair Hessians with negative
// eigenvalues (sizes of IPC pairs: 6 in 2D, 12 in 3D). Built and run by
// psd_projection.sh.
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/lapack_full_matrix.h>

#include <forma/solvers/psd_projection.h>

#include <chrono>
#include <cstdint>
#include <iostream>
#include <vector>

using namespace dealii;

static double
next(std::uint64_t &s)
{
  s = s * 6364136223846793005ULL + 1442695040888963407ULL;
  return 2. * ((s >> 11) * (1. / 9007199254740992.)) - 1.;
}

// The previous implementation: H+ = (H + V S V^T) / 2 from LAPACK's SVD.
static void
svd_projection(FullMatrix<double> &H)
{
  const unsigned int       n = H.m();
  LAPACKFullMatrix<double> A(n, n);
  A = H;
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

int
main()
{
  std::cout << "size,calls,svd_us_per_call,eigen_us_per_call,speedup\n";
  for (const unsigned int n : {6u, 12u})
    {
      std::uint64_t                   s = 3;
      std::vector<FullMatrix<double>> H(2000, FullMatrix<double>(n, n));
      for (auto &h : H)
        for (unsigned int i = 0; i < n; ++i)
          for (unsigned int j = 0; j <= i; ++j)
            h(i, j) = h(j, i) = next(s);
      double seconds[2];
      for (unsigned int method = 0; method < 2; ++method)
        {
          auto       work = H;
          const auto t0   = std::chrono::steady_clock::now();
          for (unsigned int repeat = 0; repeat < 10; ++repeat)
            for (auto &h : work)
              {
                FullMatrix<double> c = h;
                if (method == 0)
                  svd_projection(c);
                else
                  forma::project_to_psd(c, "benchmark");
              }
          seconds[method] =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
              .count();
        }
      const double calls = 10. * H.size();
      std::cout << n << "," << calls << "," << 1e6 * seconds[0] / calls << ","
                << 1e6 * seconds[1] / calls << "," << seconds[0] / seconds[1]
                << "\n";
    }
}
