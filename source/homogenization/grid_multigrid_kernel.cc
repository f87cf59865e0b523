#include "grid_multigrid_level.h"

#include <cmath>

// The hot loop of GridMultigridHomogenization: the pixel operator applied
// to one row of pixels at a time, on contiguous arrays so that it runs as
// vector instructions. Compiled with -O3 (CMakeLists.txt) and cloned for
// AVX-512 and AVX2 machines, chosen when the library loads.

namespace forma
{
  namespace internal
  {
    namespace grid_multigrid
    {
      namespace
      {
        template <typename Number>
        inline __attribute__((always_inline)) void
        pixel_row_body(const std::size_t       n,
                       const Number            ihx,
                       const Number            ihy,
                       const Number            w,
                       const PixelRow<Number> &row)
        {
          const Number g0 = 0.5 - 0.5 / std::sqrt(3.), g1 = 1 - g0;
          const Number *__restrict C0 = row.C[0], *__restrict C1 = row.C[1],
                                   *__restrict C2 = row.C[2],
                                   *__restrict C3 = row.C[3],
                                   *__restrict C4 = row.C[4],
                                   *__restrict C5 = row.C[5];
          const Number *__restrict ux0 = row.u[0], *__restrict uy0 = row.u[1],
                                   *__restrict ux1 = row.u[2],
                                   *__restrict uy1 = row.u[3];
          Number *__restrict o0x = row.out[0], *__restrict o0y = row.out[1],
                             *__restrict o1x = row.out[2],
                             *__restrict o1y = row.out[3],
                             *__restrict o2x = row.out[4],
                             *__restrict o2y = row.out[5],
                             *__restrict o3x = row.out[6],
                             *__restrict o3y = row.out[7];
          const Number wx = w * ihx, wy = w * ihy;
#pragma GCC ivdep
          for (std::size_t i = 0; i < n; ++i)
            {
              // differences along the edges: bottom, top, left, right
              const Number bx = ux0[i + 1] - ux0[i], by = uy0[i + 1] - uy0[i];
              const Number tx = ux1[i + 1] - ux1[i], ty = uy1[i + 1] - uy1[i];
              const Number lx = ux1[i] - ux0[i], ly = uy1[i] - uy0[i];
              const Number rx = ux1[i + 1] - ux0[i + 1],
                           ry = uy1[i + 1] - uy0[i + 1];
              // du/dx at the Gauss rows eta_0, eta_1; du/dy at the columns
              const Number dxx0 = (g1 * bx + g0 * tx) * ihx,
                           dxy0 = (g1 * by + g0 * ty) * ihx;
              const Number dxx1 = (g0 * bx + g1 * tx) * ihx,
                           dxy1 = (g0 * by + g1 * ty) * ihx;
              const Number dyx0 = (g1 * lx + g0 * rx) * ihy,
                           dyy0 = (g1 * ly + g0 * ry) * ihy;
              const Number dyx1 = (g0 * lx + g1 * rx) * ihy,
                           dyy1 = (g0 * ly + g1 * ry) * ihy;
              const Number c0 = C0[i], c1 = C1[i], c2 = C2[i], c3 = C3[i],
                           c4 = C4[i], c5 = C5[i];
              // stresses at Gauss point (qx, qy): strain (dx_x[qy], dy_y[qx],
              // dy_x[qx] + dx_y[qy])
              Number       sx[2][2], sy[2][2], sxy[2][2];
              const Number ex[2] = {dxx0, dxx1}, exy[2] = {dxy0, dxy1};
              const Number ey[2] = {dyy0, dyy1}, eyx[2] = {dyx0, dyx1};
              for (unsigned int qy = 0; qy < 2; ++qy)
                for (unsigned int qx = 0; qx < 2; ++qx)
                  {
                    const Number e0 = ex[qy], e1 = ey[qx],
                                 e2 = eyx[qx] + exy[qy];
                    sx[qy][qx]      = c0 * e0 + c1 * e1 + c2 * e2;
                    sy[qy][qx]      = c1 * e0 + c3 * e1 + c4 * e2;
                    sxy[qy][qx]     = c2 * e0 + c4 * e1 + c5 * e2;
                  }
              // duals of du/dx (rows) and du/dy (columns)
              const Number Tx0 = sx[0][0] + sx[0][1], Tx1 = sx[1][0] + sx[1][1];
              const Number Txy0 = sxy[0][0] + sxy[0][1],
                           Txy1 = sxy[1][0] + sxy[1][1];
              const Number Tyx0 = sxy[0][0] + sxy[1][0],
                           Tyx1 = sxy[0][1] + sxy[1][1];
              const Number Ty0 = sy[0][0] + sy[1][0], Ty1 = sy[0][1] + sy[1][1];
              const Number Dbx = wx * (g1 * Tx0 + g0 * Tx1),
                           Dby = wx * (g1 * Txy0 + g0 * Txy1);
              const Number Dtx = wx * (g0 * Tx0 + g1 * Tx1),
                           Dty = wx * (g0 * Txy0 + g1 * Txy1);
              const Number Dlx = wy * (g1 * Tyx0 + g0 * Tyx1),
                           Dly = wy * (g1 * Ty0 + g0 * Ty1);
              const Number Drx = wy * (g0 * Tyx0 + g1 * Tyx1),
                           Dry = wy * (g0 * Ty0 + g1 * Ty1);
              o0x[i]           = -Dbx - Dlx;
              o0y[i]           = -Dby - Dly;
              o1x[i]           = Dbx - Drx;
              o1y[i]           = Dby - Dry;
              o2x[i]           = -Dtx + Dlx;
              o2y[i]           = -Dty + Dly;
              o3x[i]           = Dtx + Drx;
              o3y[i]           = Dty + Dry;
            }
        }



        template <typename Number>
        inline __attribute__((always_inline)) void
        element_row_body(const std::size_t   n,
                         const Number       *K,
                         const Number *const u[4],
                         Number *const       y[4])
        {
          // K is symmetric: its rows are its columns, and out = sum_k u_k
          // K[k] runs along contiguous rows.
          const auto cell = [&](const std::size_t i, const std::size_t i1) {
            const Number ue[8]          = {u[0][i],
                                           u[1][i],
                                           u[0][i1],
                                           u[1][i1],
                                           u[2][i],
                                           u[3][i],
                                           u[2][i1],
                                           u[3][i1]};
            const Number *__restrict Ke = K + 64 * i;
            Number acc[8]               = {};
#pragma GCC unroll 8
            for (unsigned int k = 0; k < 8; ++k)
#pragma GCC ivdep
              for (unsigned int r = 0; r < 8; ++r)
                acc[r] += Ke[8 * k + r] * ue[k];
            y[0][i] += acc[0];
            y[1][i] += acc[1];
            y[0][i1] += acc[2];
            y[1][i1] += acc[3];
            y[2][i] += acc[4];
            y[3][i] += acc[5];
            y[2][i1] += acc[6];
            y[3][i1] += acc[7];
          };
          for (std::size_t i = 0; i + 1 < n; ++i)
            cell(i, i + 1);
          cell(n - 1, 0);
        }
      } // namespace



// Vector clones need GCC's function multi-versioning on x86-64.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#  define FORMA_CLONES \
    __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#  define FORMA_CLONES
#endif

      FORMA_CLONES void
      pixel_row(const std::size_t       n,
                const double            ihx,
                const double            ihy,
                const double            w,
                const PixelRow<double> &row)
      {
        pixel_row_body<double>(n, ihx, ihy, w, row);
      }

      FORMA_CLONES void
      pixel_row(const std::size_t      n,
                const double           ihx,
                const double           ihy,
                const double           w,
                const PixelRow<float> &row)
      {
        pixel_row_body<float>(n, ihx, ihy, w, row);
      }

      FORMA_CLONES void
      element_row(const std::size_t   n,
                  const double       *K,
                  const double *const u[4],
                  double *const       y[4])
      {
        element_row_body<double>(n, K, u, y);
      }

      FORMA_CLONES void
      element_row(const std::size_t  n,
                  const float       *K,
                  const float *const u[4],
                  float *const       y[4])
      {
        element_row_body<float>(n, K, u, y);
      }
#undef FORMA_CLONES
    } // namespace grid_multigrid
  }   // namespace internal
} // namespace forma
