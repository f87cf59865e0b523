#include "grid_multigrid_level.h"

#include <cmath>

// The transfers between GridMultigridHomogenization's grids: the
// interpolation weights (bilinear or operator-dependent) and the Galerkin
// coarse element matrices they give.

namespace forma
{
  namespace internal
  {
    namespace grid_multigrid
    {
      using dealii::Vector;

      namespace
      {
        /// A 2 x 2 block, row-major.
        using Block = std::array<double, 4>;

        Block
        operator*(const Block &A, const Block &B)
        {
          return {{A[0] * B[0] + A[1] * B[2],
                   A[0] * B[1] + A[1] * B[3],
                   A[2] * B[0] + A[3] * B[2],
                   A[2] * B[1] + A[3] * B[3]}};
        }

        Block &
        operator+=(Block &A, const Block &B)
        {
          for (unsigned int k = 0; k < 4; ++k)
            A[k] += B[k];
          return A;
        }

        /// -A^-1
        Block
        minus_inverse(const Block &A)
        {
          const double det = A[0] * A[3] - A[1] * A[2];
          return {{-A[3] / det, A[1] / det, A[2] / det, -A[0] / det}};
        }

        const Block identity = {{1, 0, 0, 1}};

        /// Node (i, j)'s row of the operator: S[dx + 1][dy + 1] couples it
        /// to the node at offset (dx, dy), from the four cells around it.
        template <typename Number>
        void
        node_stencil(const Level<Number> &level,
                     const unsigned int   i,
                     const unsigned int   j,
                     Block                S[3][3])
        {
          for (unsigned int x = 0; x < 3; ++x)
            for (unsigned int y = 0; y < 3; ++y)
              S[x][y].fill(0.);
          double K[64];
          for (unsigned int b = 0; b < 2; ++b)
            for (unsigned int a = 0; a < 2; ++a)
              {
                // the cell whose local node (1 - a, 1 - b) is (i, j)
                const unsigned int ci = (i + level.nx - 1 + a) % level.nx;
                const unsigned int cj = (j + level.ny - 1 + b) % level.ny;
                level.cell_matrix(ci + level.nx * std::size_t(cj), K);
                const unsigned int kF = (1 - a) + 2 * (1 - b);
                for (unsigned int kN = 0; kN < 4; ++kN)
                  {
                    Block &s = S[kN % 2 + a][kN / 2 + b];
                    for (unsigned int c = 0; c < 2; ++c)
                      for (unsigned int d = 0; d < 2; ++d)
                        s[2 * c + d] += K[8 * (2 * kF + c) + 2 * kN + d];
                  }
              }
        }

        /// Weight block W_ab of a node's prolongation entry.
        Block
        weight(const std::array<float, 16> &w,
               const unsigned int           a,
               const unsigned int           b)
        {
          const unsigned int o = 4 * (2 * b + a);
          return {{w[o], w[o + 1], w[o + 2], w[o + 3]}};
        }

        void
        set_weight(std::array<float, 16> &w,
                   const unsigned int     a,
                   const unsigned int     b,
                   const Block           &W)
        {
          std::copy(W.begin(), W.end(), w.begin() + 4 * (2 * b + a));
        }

        /// A node between coarse nodes along x (vertical: along y): the
        /// stencil collapsed onto the line.
        void
        line_weights(const Block            S[3][3],
                     const bool             along_x,
                     std::array<float, 16> &w)
        {
          Block Abar[3] = {};
          for (unsigned int x = 0; x < 3; ++x)
            for (unsigned int y = 0; y < 3; ++y)
              Abar[along_x ? x : y] += S[x][y];
          const Block M = minus_inverse(Abar[1]);
          set_weight(w, 0, 0, M * Abar[0]);
          set_weight(w, along_x ? 1 : 0, along_x ? 0 : 1, M * Abar[2]);
        }

        /// Bilinear weights of a node on a coarse line (a, b: its offsets
        /// 0 or 1 from its first coarse node) or inside a coarse cell.
        void
        bilinear_weights(const unsigned int     a,
                         const unsigned int     b,
                         std::array<float, 16> &w)
        {
          w.fill(0.f);
          const double f    = a == 1 && b == 1 ? 0.25 : 0.5;
          const Block  part = {{f, 0, 0, f}};
          for (unsigned int k = 0; k < 4; ++k)
            if (k % 2 <= a && k / 2 <= b)
              set_weight(w, k % 2, k / 2, part);
        }

        /// Operator-dependent weights are affine (they sum to the identity)
        /// and near [0, 1] where the stencil they come from is well
        /// conditioned; a weight beyond 2 marks a nearly singular one
        /// (solid and void meeting across a coarse cell at a point, thin
        /// beams), whose interpolation would spoil the coarse grids.
        bool
        bounded(const std::array<float, 16> &w)
        {
          for (const float v : w)
            if (!(std::abs(v) <= 2.f))
              return false;
          return true;
        }

        template <typename Number>
        void
        set_prolongation(Level<Number> &fine, const bool operator_dependent)
        {
          const unsigned int nx = fine.nx, ny = fine.ny;
          fine.prolongation.assign(std::size_t(nx) * ny, {});
          const auto node =
            [&](const unsigned int i,
                const unsigned int j) -> std::array<float, 16> & {
            return fine.prolongation[i % nx + nx * std::size_t(j % ny)];
          };
          Block S[3][3];
          // Coarse nodes and the nodes on coarse lines first: the nodes
          // inside coarse cells interpolate through them.
          for (unsigned int j = 0; j < ny; ++j)
            for (unsigned int i = 0; i < nx; ++i)
              {
                auto &w = node(i, j);
                if (i % 2 == 0 && j % 2 == 0)
                  set_weight(w, 0, 0, identity);
                else if (i % 2 == 1 && j % 2 == 1)
                  continue;
                else if (!operator_dependent)
                  bilinear_weights(i % 2, j % 2, w);
                else
                  {
                    node_stencil(fine, i, j, S);
                    line_weights(S, i % 2 == 1, w);
                    if (!bounded(w))
                      bilinear_weights(i % 2, j % 2, w);
                  }
              }
          for (unsigned int j = 1; j < ny; j += 2)
            for (unsigned int i = 1; i < nx; i += 2)
              {
                auto &w = node(i, j);
                if (!operator_dependent)
                  {
                    bilinear_weights(1, 1, w);
                    continue;
                  }
                node_stencil(fine, i, j, S);
                // T_ab = sum over the neighbours of S[nbr] W_nbr, in this
                // cell's corners (a, b).
                Block T[2][2] = {};
                for (unsigned int x = 0; x < 3; ++x)
                  for (unsigned int y = 0; y < 3; ++y)
                    {
                      if (x == 1 && y == 1)
                        continue;
                      const auto &wn = node(i + x + nx - 1, j + y + ny - 1);
                      // the neighbour's corners are this cell's shifted by
                      // x / 2, y / 2
                      for (unsigned int b = 0; b < 2; ++b)
                        for (unsigned int a = 0; a < 2; ++a)
                          {
                            const unsigned int A = a + x / 2, B = b + y / 2;
                            if (A < 2 && B < 2)
                              T[A][B] += S[x][y] * weight(wn, a, b);
                          }
                    }
                const Block M = minus_inverse(S[1][1]);
                for (unsigned int b = 0; b < 2; ++b)
                  for (unsigned int a = 0; a < 2; ++a)
                    set_weight(w, a, b, M * T[a][b]);
                if (!bounded(w))
                  bilinear_weights(1, 1, w);
              }
        }
      } // namespace



      template <typename Number>
      Level<Number>
      coarsen(Level<Number> &fine, const bool operator_dependent)
      {
        Level<Number> coarse;
        coarse.nx = (fine.nx + 1) / 2;
        coarse.ny = (fine.ny + 1) / 2;
        set_prolongation(fine, operator_dependent);
        coarse.element.assign(64 * std::size_t(coarse.nx) * coarse.ny, 0.);
        double K[64];
        for (unsigned int j = 0; j < fine.ny; ++j)
          for (unsigned int i = 0; i < fine.nx; ++i)
            {
              fine.cell_matrix(i + fine.nx * std::size_t(j), K);
              const unsigned int I = i / 2, J = j / 2;
              // P[k][L]: the block of coarse corner L of cell (I, J) at the
              // child's local node k
              Block P[4][4];
              for (unsigned int k = 0; k < 4; ++k)
                {
                  const unsigned int fi = i + k % 2, fj = j + k / 2;
                  const auto        &w =
                    fine.prolongation[fi % fine.nx +
                                      fine.nx * std::size_t(fj % fine.ny)];
                  for (unsigned int L = 0; L < 4; ++L)
                    P[k][L].fill(0.);
                  for (unsigned int b = 0; b < 2; ++b)
                    for (unsigned int a = 0; a < 2; ++a)
                      {
                        // corner (I_node + a) of the node, as a corner of
                        // (I, J): 0 or 1 (wrapped; on grids of one or two
                        // coarse cells the corners coincide anyway)
                        const unsigned int X =
                          ((fi % fine.nx) / 2 + a + coarse.nx - I) % coarse.nx;
                        const unsigned int Y =
                          ((fj % fine.ny) / 2 + b + coarse.ny - J) % coarse.ny;
                        if (X < 2 && Y < 2)
                          P[k][X + 2 * Y] += weight(w, a, b);
                      }
                }
              Number *Kc =
                &coarse.element[64 * (I + coarse.nx * std::size_t(J))];
              // Kc += P^T K P, by blocks
              for (unsigned int L = 0; L < 4; ++L)
                for (unsigned int M = 0; M < 4; ++M)
                  {
                    Block sum = {};
                    for (unsigned int k = 0; k < 4; ++k)
                      {
                        Block KP = {};
                        for (unsigned int l = 0; l < 4; ++l)
                          {
                            const Block Kkl = {
                              {K[8 * (2 * k) + 2 * l],
                               K[8 * (2 * k) + 2 * l + 1],
                               K[8 * (2 * k + 1) + 2 * l],
                               K[8 * (2 * k + 1) + 2 * l + 1]}};
                            KP += Kkl * P[l][M];
                          }
                        const Block &W  = P[k][L];
                        const Block  Wt = {{W[0], W[2], W[1], W[3]}};
                        sum += Wt * KP;
                      }
                    for (unsigned int c = 0; c < 2; ++c)
                      for (unsigned int d = 0; d < 2; ++d)
                        Kc[8 * (2 * L + c) + 2 * M + d] += sum[2 * c + d];
                  }
            }
        coarse.compute_diagonal();
        return coarse;
      }



      namespace
      {
        /**
         * Call f(fine node, W, coarse node) for every fine node and each of
         * its coarse parents with a weight (one on coarse nodes, two on
         * coarse lines, four inside coarse cells), row by row.
         */
        template <typename Number, typename F>
        void
        for_each_parent(const Level<Number> &fine,
                        const Level<Number> &coarse,
                        const F             &f)
        {
          for (std::size_t j = 0; j < fine.ny; ++j)
            {
              const std::size_t  J[2] = {coarse.nx * (j / 2),
                                         coarse.nx * ((j / 2 + 1) % coarse.ny)};
              const unsigned int nb   = 1 + j % 2;
              for (std::size_t i = 0; i < fine.nx; ++i)
                {
                  const std::size_t I[2] = {
                    i / 2, (i / 2 + 1 == coarse.nx) ? 0 : i / 2 + 1};
                  const unsigned int na   = 1 + i % 2;
                  const std::size_t  node = i + fine.nx * j;
                  const float       *w    = fine.prolongation[node].data();
                  for (unsigned int b = 0; b < nb; ++b)
                    for (unsigned int a = 0; a < na; ++a)
                      f(node, w + 4 * (2 * b + a), I[a] + J[b]);
                }
            }
        }
      } // namespace



      template <typename Number>
      void
      prolongate_add(const Level<Number>  &fine,
                     const Level<Number>  &coarse,
                     Vector<Number>       &fine_vector,
                     const Vector<Number> &coarse_vector)
      {
        constexpr unsigned int n_cases = Level<Number>::n_cases;
        const std::size_t      N = fine.n_nodes(), Nc = coarse.n_nodes();
        Number                *u[2 * n_cases];
        const Number          *uc[2 * n_cases];
        for (unsigned int k = 0; k < 2 * n_cases; ++k)
          {
            u[k]  = fine_vector.begin() + k * N;
            uc[k] = coarse_vector.begin() + k * Nc;
          }
        for_each_parent(
          fine,
          coarse,
          [&](const std::size_t f, const float *W, const std::size_t c) {
            for (unsigned int r = 0; r < n_cases; ++r)
              {
                const Number x = uc[2 * r][c], y = uc[2 * r + 1][c];
                u[2 * r][f] += W[0] * x + W[1] * y;
                u[2 * r + 1][f] += W[2] * x + W[3] * y;
              }
          });
      }



      template <typename Number>
      void
      restrict_to(const Level<Number>  &fine,
                  const Level<Number>  &coarse,
                  const Vector<Number> &fine_vector,
                  Vector<Number>       &coarse_vector)
      {
        constexpr unsigned int n_cases = Level<Number>::n_cases;
        coarse_vector.reinit(coarse.m());
        const std::size_t N = fine.n_nodes(), Nc = coarse.n_nodes();
        const Number     *u[2 * n_cases];
        Number           *uc[2 * n_cases];
        for (unsigned int k = 0; k < 2 * n_cases; ++k)
          {
            u[k]  = fine_vector.begin() + k * N;
            uc[k] = coarse_vector.begin() + k * Nc;
          }
        for_each_parent(fine,
                        coarse,
                        [&](const std::size_t f,
                            const float      *W,
                            const std::size_t c) {
                          for (unsigned int r = 0; r < n_cases; ++r)
                            {
                              const Number x = u[2 * r][f], y = u[2 * r + 1][f];
                              uc[2 * r][c] += W[0] * x + W[2] * y;
                              uc[2 * r + 1][c] += W[1] * x + W[3] * y;
                            }
                        });
      }


      template Level<float>
      coarsen(Level<float> &, bool);
      template void
      prolongate_add(const Level<float> &,
                     const Level<float> &,
                     Vector<float> &,
                     const Vector<float> &);
      template void
      restrict_to(const Level<float> &,
                  const Level<float> &,
                  const Vector<float> &,
                  Vector<float> &);
    } // namespace grid_multigrid
  }   // namespace internal
} // namespace forma
