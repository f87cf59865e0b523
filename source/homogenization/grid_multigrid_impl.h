#ifndef forma_source_homogenization_grid_multigrid_impl_h
#define forma_source_homogenization_grid_multigrid_impl_h

// GridMultigridHomogenization's state, shared by its files (internal, not
// installed): the hierarchy and solves (grid_multigrid.cc) and the output
// (grid_multigrid_output.cc).

#include <deal.II/lac/lapack_full_matrix.h>
#include <deal.II/lac/precondition.h>

#include <forma/homogenization/grid_multigrid.h>

#include "grid_multigrid_level.h"

#include <memory>
#include <vector>

namespace forma
{
  namespace internal
  {
    namespace grid_multigrid
    {
      /// The unit test strain a (Voigt, engineering shear).
      inline constexpr double test_strain[3][3] = {{1, 0, 0},
                                                   {0, 1, 0},
                                                   {0, 0, 1}};
    } // namespace grid_multigrid
  }   // namespace internal

  using namespace internal::grid_multigrid;

  struct GridMultigridHomogenization::Impl
  {
    using Smoother =
      dealii::PreconditionChebyshev<Level<float>, dealii::Vector<float>>;

    Parameters parameters;
    /// The pixels in double precision: the operator CG solves.
    Level<double> fine;
    /// The V-cycle's grids in single precision, the pixels' first.
    std::vector<Level<float>>              levels;
    std::vector<std::unique_ptr<Smoother>> smoothers;
    dealii::LAPACKFullMatrix<double>       coarsest;
    /// the fluctuations of the three test strains, one block each
    dealii::Vector<double> solution;
    /// Per level: residual, and the coarse right-hand side and correction.
    mutable std::vector<dealii::Vector<float>> residual, coarse_rhs, correction;
    double                                     volume = 0;

    void
    build_hierarchy();

    void
    factorize_coarsest();

    /// x = V-cycle(b) on level l.
    void
    v_cycle(const unsigned int           l,
            dealii::Vector<float>       &x,
            const dealii::Vector<float> &b) const;

    /// The strains at the Gauss points of pixel c under test strain a.
    void
    strains(const unsigned int i,
            const unsigned int j,
            const unsigned int a,
            double             eps[4][3]) const
    {
      double u[8];
      gather(fine, i, j, solution.begin() + a * fine.block_size(), u);
      pixel_strains(u, test_strain[a], fine.hx, fine.hy, eps);
    }

    void
    vmult(dealii::Vector<double> &x, const dealii::Vector<double> &b) const
    {
      b_single = b;
      x_single.reinit(b.size(), true);
      v_cycle(0, x_single, b_single);
      x = x_single;
    }

    /// vmult()'s vectors in single precision
    mutable dealii::Vector<float> x_single, b_single;
  };



} // namespace forma

#endif
