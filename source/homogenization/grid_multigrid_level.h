#ifndef forma_source_homogenization_grid_multigrid_level_h
#define forma_source_homogenization_grid_multigrid_level_h

// One grid of GridMultigridHomogenization's hierarchy (internal, not
// installed): the periodic Q1 operator without a matrix, its Galerkin
// coarsening and the transfers between grids.

#include <deal.II/base/subscriptor.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <vector>

namespace forma
{
  namespace internal
  {
    namespace grid_multigrid
    {
      /// Pixel tensor in Voigt form (engineering shear): C00 C01 C02 C11 C12
      /// C22 of the symmetric 3 x 3 matrix.
      using Voigt = std::array<double, 6>;

      /**
       * An nx x ny periodic grid of Q1 cells: node (i, j) is number
       * i + nx j, and the dof of its component c is c n_nodes + node (rows
       * of nodes load as vectors). Vectors hold the three test
       * strains' fields one after the other (`n_cases` blocks of
       * block_size()), and the operator acts on each: one pass over the
       * grid's tensors or matrices serves all three. The finest grid keeps one
       * Voigt tensor per cell and integrates on the fly; coarser grids
       * keep the Galerkin element matrices P^T K P of their cells (8 x 8,
       * local nodes (0,0), (1,0), (0,1), (1,1)). Number is double for the
       * operator CG solves, float for the V-cycle that preconditions it
       * (half the memory traffic).
       */
      template <typename Number>
      struct Level : public dealii::Subscriptor
      {
        static constexpr unsigned int n_cases = 3;

        unsigned int nx = 0, ny = 0;
        double       hx = 0, hy = 0; ///< finest grid: cell size
        /// finest grid: the pixels' Voigt tensors, entry by entry
        /// (voigt[l][pixel]: rows of pixels load as vectors)
        std::array<std::vector<Number>, 6> voigt;
        /// finest grid: the pixel matrix of each unit Voigt entry
        std::array<std::array<double, 64>, 6> basis{};
        std::vector<Number>    element;  ///< coarser grids: 64 per cell
        dealii::Vector<Number> diagonal; ///< of one block
        /**
         * The interpolation from the next coarser grid (set by coarsen()):
         * node (i, j) takes sum_ab W_ab u(I + a, J + b), I = i / 2,
         * J = j / 2 (wrapped), with the 2 x 2 block W_ab at
         * prolongation[node][4 (2 b + a) + 2 c + d] (row c, column d).
         * Single precision: the coarse operators are Galerkin products of
         * these very weights, so rounding changes the preconditioner only.
         */
        std::vector<std::array<float, 16>> prolongation;

        using size_type = dealii::types::global_dof_index;

        size_type
        n_nodes() const
        {
          return static_cast<size_type>(nx) * ny;
        }

        /// dofs of one test strain's field
        size_type
        block_size() const
        {
          return 2 * n_nodes();
        }

        size_type
        m() const
        {
          return n_cases * block_size();
        }

        size_type
        n() const
        {
          return m();
        }

        Number
        el(const size_type i, const size_type j) const
        {
          (void)j;
          return diagonal(i % block_size());
        }

        /// dst = A src, block by block
        void
        vmult(dealii::Vector<Number>       &dst,
              const dealii::Vector<Number> &src) const;

        /// vmult() on the finest grid, a row of pixels at a time
        void
        pixel_vmult(dealii::Vector<Number>       &dst,
                    const dealii::Vector<Number> &src) const;

        void
        Tvmult(dealii::Vector<Number>       &dst,
               const dealii::Vector<Number> &src) const
        {
          vmult(dst, src);
        }

        bool
        is_pixel_grid() const
        {
          return !voigt[0].empty();
        }

        /// finest grid: the tensor of pixel c
        Voigt
        pixel(const std::size_t c) const
        {
          return {{voigt[0][c],
                   voigt[1][c],
                   voigt[2][c],
                   voigt[3][c],
                   voigt[4][c],
                   voigt[5][c]}};
        }

        /// The element matrix of cell c (finest grid: from its tensor).
        void
        cell_matrix(const std::size_t c, double K[64]) const;

        /// Fill `diagonal` from the element matrices.
        void
        compute_diagonal();
      };

      /// The finest grid: nx x ny pixels of size hx x hy (tensors unset).
      template <typename Number>
      Level<Number>
      pixel_level(const unsigned int nx,
                  const unsigned int ny,
                  const double       hx,
                  const double       hy);

      /**
       * The Galerkin coarse grid P^T A P of `fine`: ceil(n/2) cells along
       * each direction (with n odd, the last coarse cell spans one fine
       * cell). Sets fine.prolongation: bilinear interpolation, or
       * (`operator_dependent`) weights from fine's own stencils, as in
       * black-box multigrid for systems (Dendy): a node between two coarse
       * nodes takes -A0^-1 A(-1), -A0^-1 A(+1) of its stencil collapsed
       * along the line, a node inside a coarse cell solves its own row
       * given its neighbours. They follow the stiff phase across a strong
       * contrast, where bilinear interpolation mixes it with the soft one.
       */
      template <typename Number>
      Level<Number>
      coarsen(Level<Number> &fine, const bool operator_dependent);

      /// A copy of a grid in single precision (tensors and matrices).
      Level<float>
      single_precision(const Level<double> &level);

      /// fine += P coarse
      template <typename Number>
      void
      prolongate_add(const Level<Number>          &fine,
                     const Level<Number>          &coarse,
                     dealii::Vector<Number>       &fine_vector,
                     const dealii::Vector<Number> &coarse_vector);

      /// coarse = P^T fine
      template <typename Number>
      void
      restrict_to(const Level<Number>          &fine,
                  const Level<Number>          &coarse,
                  const dealii::Vector<Number> &fine_vector,
                  dealii::Vector<Number>       &coarse_vector);

      /**
       * The Voigt strains at the 2 x 2 Gauss points of a pixel with nodal
       * values u (local node k, component c at 2 k + c) plus the constant
       * strain A (may be null).
       */
      void
      pixel_strains(const double  u[8],
                    const double *A,
                    const double  hx,
                    const double  hy,
                    double        eps[4][3]);

      /// The nodes of cell (i, j), local order.
      template <typename Number>
      inline std::array<std::size_t, 4>
      cell_nodes(const Level<Number> &level,
                 const unsigned int   i,
                 const unsigned int   j)
      {
        const std::size_t i1 = (i + 1) % level.nx, j1 = (j + 1) % level.ny;
        return {{i + level.nx * std::size_t(j),
                 i1 + level.nx * std::size_t(j),
                 i + level.nx * j1,
                 i1 + level.nx * j1}};
      }

      /// Gather the 8 nodal values of cell (i, j) from a block at v.
      template <typename Number>
      inline void
      gather(const Level<Number> &level,
             const unsigned int   i,
             const unsigned int   j,
             const double        *v,
             double               u[8])
      {
        const auto        node = cell_nodes(level, i, j);
        const std::size_t N    = level.n_nodes();
        for (unsigned int k = 0; k < 4; ++k)
          {
            u[2 * k]     = v[node[k]];
            u[2 * k + 1] = v[N + node[k]];
          }
      }

      /// Scatter-add the 8 local values of cell (i, j) to a block at v.
      template <typename Number, typename Value>
      inline void
      scatter_add(const Level<Number> &level,
                  const unsigned int   i,
                  const unsigned int   j,
                  const double         y[8],
                  Value               *v)
      {
        const auto        node = cell_nodes(level, i, j);
        const std::size_t N    = level.n_nodes();
        for (unsigned int k = 0; k < 4; ++k)
          {
            v[node[k]] += y[2 * k];
            v[N + node[k]] += y[2 * k + 1];
          }
      }

      /// One row of pixels for pixel_row(): their tensor entries, the
      /// components of u on the row's lower and upper nodes (x0, y0, x1,
      /// y1: n + 1 each, node n being the row's first again) and the
      /// outputs of local nodes 0..3 (x, y each).
      template <typename Number>
      struct PixelRow
      {
        const Number *C[6];
        const Number *u[4];
        Number       *out[8];
      };

      /// The pixel operator on n pixels of a row.
      void
      pixel_row(const std::size_t       n,
                const double            ihx,
                const double            ihy,
                const double            w,
                const PixelRow<double> &row);

      void
      pixel_row(const std::size_t      n,
                const double           ihx,
                const double           ihy,
                const double           w,
                const PixelRow<float> &row);

      /**
       * The element matrices K (64 per cell, symmetric) of the n cells of
       * a row applied to u, added to y: u[0], u[1] the x and y components
       * on the row's lower nodes, u[2], u[3] on its upper nodes (n values
       * each; the last cell wraps around to node 0), y alike. With n = 1
       * a cell's two nodes along the row are one.
       */
      void
      element_row(const std::size_t   n,
                  const double       *K,
                  const double *const u[4],
                  double *const       y[4]);

      void
      element_row(const std::size_t  n,
                  const float       *K,
                  const float *const u[4],
                  float *const       y[4]);

      /// The load of a pixel under the constant strain A: int B^T C A.
      void
      pixel_load(const Level<double> &level,
                 const std::size_t    c,
                 const double         A[3],
                 double               f[8]);
    } // namespace grid_multigrid
  }   // namespace internal
} // namespace forma

#endif
