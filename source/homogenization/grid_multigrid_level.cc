#include "grid_multigrid_level.h"

#include <cmath>

// The periodic Q1 operator of GridMultigridHomogenization's grids, their
// Galerkin coarsening and the grid transfers.

namespace forma
{
  namespace internal
  {
    namespace grid_multigrid
    {
      using dealii::Vector;

      namespace
      {
        // Gauss points of [0, 1].
        const double gauss[2] = {0.5 - 0.5 / std::sqrt(3.),
                                 0.5 + 0.5 / std::sqrt(3.)};

      } // namespace



      template <typename Number>
      Level<Number>
      pixel_level(const unsigned int nx,
                  const unsigned int ny,
                  const double       hx,
                  const double       hy)
      {
        Level<Number> level;
        level.nx = nx;
        level.ny = ny;
        level.hx = hx;
        level.hy = hy;
        // The pixel matrix of each unit Voigt entry, column by column, from
        // the row kernel on a row of one pixel.
        for (unsigned int l = 0; l < 6; ++l)
          {
            double C[6] = {}, u[4][2], out[8];
            C[l]        = 1;
            PixelRow<double> row;
            for (unsigned int e = 0; e < 6; ++e)
              row.C[e] = &C[e];
            for (unsigned int k = 0; k < 8; ++k)
              row.out[k] = &out[k];
            for (unsigned int k = 0; k < 8; ++k)
              {
                // local node k / 2, component k % 2: row (lower or upper)
                // and component pick u's array, the node's x its entry
                for (unsigned int a = 0; a < 4; ++a)
                  u[a][0] = u[a][1] = 0;
                u[2 * (k / 4) + k % 2][(k / 2) % 2] = 1;
                for (unsigned int a = 0; a < 4; ++a)
                  row.u[a] = u[a];
                pixel_row(1, 1 / hx, 1 / hy, hx * hy / 4, row);
                for (unsigned int r = 0; r < 8; ++r)
                  level.basis[l][8 * r + k] = out[r];
              }
          }
        return level;
      }



      template <typename Number>
      void
      Level<Number>::cell_matrix(const std::size_t c, double K[64]) const
      {
        if (!is_pixel_grid())
          {
            std::copy(&element[64 * c], &element[64 * c] + 64, K);
            return;
          }
        for (unsigned int r = 0; r < 64; ++r)
          K[r] = 0;
        for (unsigned int l = 0; l < 6; ++l)
          for (unsigned int r = 0; r < 64; ++r)
            K[r] += voigt[l][c] * basis[l][r];
      }



      template <typename Number>
      void
      Level<Number>::vmult(Vector<Number> &dst, const Vector<Number> &src) const
      {
        dst = 0;
        if (is_pixel_grid())
          {
            pixel_vmult(dst, src);
            return;
          }
        const std::size_t n = nx, N = n_nodes();
        for (std::size_t j = 0; j < ny; ++j)
          {
            const std::size_t r0 = n * j, r1 = n * (j + 1 == ny ? 0 : j + 1);
            // the row's matrices stay in cache for the next case
            for (unsigned int c = 0; c < n_cases; ++c)
              {
                const Number       *u       = src.begin() + c * block_size();
                Number             *y       = dst.begin() + c * block_size();
                const Number *const urow[4] = {u + r0,
                                               u + N + r0,
                                               u + r1,
                                               u + N + r1};
                Number *const       yrow[4] = {y + r0,
                                               y + N + r0,
                                               y + r1,
                                               y + N + r1};
                element_row(n, &element[64 * r0], urow, yrow);
              }
          }
      }



      template <typename Number>
      void
      Level<Number>::pixel_vmult(Vector<Number>       &dst,
                                 const Vector<Number> &src) const
      {
        const std::size_t   n = nx, N = n_nodes();
        std::vector<Number> buffer(4 * (n + 1) + 8 * n);
        PixelRow<Number>    row;
        for (unsigned int k = 0; k < 4; ++k)
          row.u[k] = &buffer[k * (n + 1)];
        for (unsigned int k = 0; k < 8; ++k)
          row.out[k] = &buffer[4 * (n + 1) + k * n];
        for (std::size_t j = 0; j < ny; ++j)
          {
            const std::size_t r[2] = {n * j, n * (j + 1 == ny ? 0 : j + 1)};
            for (unsigned int l = 0; l < 6; ++l)
              row.C[l] = &voigt[l][r[0]];
            // the row's tensors stay in cache for the next case
            for (unsigned int c = 0; c < n_cases; ++c)
              {
                const Number *u = src.begin() + c * block_size();
                Number       *y = dst.begin() + c * block_size();
                // the rows' nodes with the first one again at the end
                for (unsigned int k = 0; k < 4; ++k)
                  {
                    const Number *from = u + (k % 2) * N + r[k / 2];
                    Number       *to   = &buffer[k * (n + 1)];
                    std::copy(from, from + n, to);
                    to[n] = from[0];
                  }
                pixel_row(n, 1 / hx, 1 / hy, hx * hy / 4, row);
                // node i of each row gathers the cell on its right (local
                // node 0 or 2) and the one on its left (1 or 3)
                for (unsigned int side = 0; side < 2; ++side)
                  for (unsigned int comp = 0; comp < 2; ++comp)
                    {
                      const Number *right = row.out[4 * side + comp];
                      const Number *left  = row.out[4 * side + 2 + comp];
                      Number       *ys    = y + comp * N + r[side];
                      ys[0] += right[0] + left[n - 1];
                      for (std::size_t i = 1; i < n; ++i)
                        ys[i] += right[i] + left[i - 1];
                    }
              }
          }
      }



      template <typename Number>
      void
      Level<Number>::compute_diagonal()
      {
        diagonal.reinit(block_size());
        double K[64];
        for (unsigned int j = 0; j < ny; ++j)
          for (unsigned int i = 0; i < nx; ++i)
            {
              cell_matrix(i + nx * std::size_t(j), K);
              // a grid one cell wide or high: a cell's nodes coincide
              const auto node = cell_nodes(*this, i, j);
              double     d[8] = {};
              for (unsigned int r = 0; r < 8; ++r)
                for (unsigned int k = 0; k < 8; ++k)
                  if (node[k / 2] == node[r / 2] && k % 2 == r % 2)
                    d[r] += K[8 * r + k];
              // scatter_add() adds d[r] at every r of a node: once per node
              for (unsigned int r = 0; r < 8; ++r)
                for (unsigned int k = 0; k < r; ++k)
                  if (node[k / 2] == node[r / 2] && k % 2 == r % 2)
                    d[r] = 0;
              scatter_add(*this, i, j, d, diagonal.begin());
            }
      }



      Level<float>
      single_precision(const Level<double> &level)
      {
        Level<float> copy;
        copy.nx    = level.nx;
        copy.ny    = level.ny;
        copy.hx    = level.hx;
        copy.hy    = level.hy;
        copy.basis = level.basis;
        for (unsigned int l = 0; l < 6; ++l)
          copy.voigt[l].assign(level.voigt[l].begin(), level.voigt[l].end());
        copy.element.assign(level.element.begin(), level.element.end());
        copy.diagonal = level.diagonal;
        return copy;
      }



      template struct Level<double>;
      template struct Level<float>;
      template Level<double>
      pixel_level<double>(unsigned int, unsigned int, double, double);



      void
      pixel_strains(const double  u[8],
                    const double *A,
                    const double  hx,
                    const double  hy,
                    double        eps[4][3])
      {
        for (unsigned int qy = 0; qy < 2; ++qy)
          for (unsigned int qx = 0; qx < 2; ++qx)
            {
              const double eta = gauss[qy], xi = gauss[qx];
              double       gx[2], gy[2];
              for (unsigned int c = 0; c < 2; ++c)
                {
                  gx[c] = ((1 - eta) * (u[2 + c] - u[c]) +
                           eta * (u[6 + c] - u[4 + c])) /
                          hx;
                  gy[c] = ((1 - xi) * (u[4 + c] - u[c]) +
                           xi * (u[6 + c] - u[2 + c])) /
                          hy;
                }
              double *e = eps[2 * qy + qx];
              e[0]      = gx[0] + (A ? A[0] : 0.);
              e[1]      = gy[1] + (A ? A[1] : 0.);
              e[2]      = gy[0] + gx[1] + (A ? A[2] : 0.);
            }
      }



      void
      pixel_load(const Level<double> &level,
                 const std::size_t    c,
                 const double         A[3],
                 double               f[8])
      {
        // int B^T C A = K u_A for the affine u_A whose strain is A, which
        // Q1 represents exactly: u_A(x, y) = (A0 x + A2 y / 2,
        // A2 x / 2 + A1 y) at the local nodes.
        double u[8];
        for (unsigned int k = 0; k < 4; ++k)
          {
            const double x = (k % 2) * level.hx, y = (k / 2) * level.hy;
            u[2 * k]     = A[0] * x + A[2] * y / 2;
            u[2 * k + 1] = A[2] * x / 2 + A[1] * y;
          }
        double K[64];
        level.cell_matrix(c, K);
        for (unsigned int r = 0; r < 8; ++r)
          {
            f[r] = 0;
            for (unsigned int k = 0; k < 8; ++k)
              f[r] += K[8 * r + k] * u[k];
          }
      }
    } // namespace grid_multigrid
  }   // namespace internal
} // namespace forma
