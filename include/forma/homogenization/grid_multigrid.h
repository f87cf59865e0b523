#ifndef forma_homogenization_grid_multigrid_h
#define forma_homogenization_grid_multigrid_h

#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace forma
{
  /**
   * Periodic homogenization of a 2D image: the same Q1 finite element
   * problem as PeriodicHomogenization on a regular grid (one constant
   * tensor per pixel, 2 x 2 Gauss points, the mutual energies of the unit
   * test strains), solved without a matrix. CG on the periodic grid in
   * double precision, preconditioned by a geometric multigrid V-cycle in
   * single precision (half the memory traffic): coarse operators are
   * Galerkin products P^T A P, kept as element matrices of the coarse grids,
   * with black-box (operator-dependent) interpolation, so strong contrasts
   * such as void survive coarsening; Chebyshev-Jacobi smoothing; a dense
   * solve on the coarsest grid. Odd grid sizes coarsen too (one coarse
   * element then spans a single cell). The pixel operator runs a row of
   * pixels at a time as AVX-512/AVX2 vector code where the CPU has it.
   *
   * The three test strains are solved together (one CG on the three
   * fields), so every pass over the pixels' tensors and the coarse grids'
   * matrices serves all three. Memory is about 100 doubles per pixel (no
   * matrix on the pixels); one process. C^H is a minimum of energies, so
   * its error is about quadratic in the solver's: `tolerance` 1e-6 gives
   * C^H to 1e-10 relative on the test images (random two-phase pixels at
   * contrast 1e-3, family structures with void 1e-6), 1e-5 to 6e-9.
   * Strongly anisotropic pixels (laminates with void) defeat the point
   * smoother: hundreds of CG steps.
   */
  class GridMultigridHomogenization
  {
  public:
    struct Parameters
    {
      /// Relative residual at which CG stops.
      double       tolerance      = 1e-6;
      unsigned int max_iterations = 1000;
      /// Chebyshev degree of the pre- and post-smoothing.
      unsigned int smoothing_degree = 3;
      /// Interpolation from the stencils (black-box multigrid) instead of
      /// bilinear: far fewer CG steps across strong contrasts.
      bool operator_dependent = true;
      /// Grids with at most this many nodes (16 to 4096) are solved
      /// directly.
      unsigned int coarsest_nodes = 256;
    };

    struct Result
    {
      dealii::SymmetricTensor<4, 2> C;
      /// CG steps (the three test strains are solved together)
      unsigned int iterations = 0;
    };

    /// An n_cells[0] x n_cells[1] pixel grid on [0, size]; pixel (i, j) is
    /// number i + n_cells[0] j.
    GridMultigridHomogenization(const dealii::Point<2>            &size,
                                const std::array<unsigned int, 2> &n_cells,
                                const Parameters                  &parameters);

    ~GridMultigridHomogenization();

    /// C^H of the pixels' tensors (one per pixel, numbered as above).
    Result
    homogenize(const std::vector<dealii::SymmetricTensor<4, 2>> &pixel_tensors);

    /// The same, asking each pixel's tensor in turn (no copy of them all).
    Result
    homogenize(
      const std::function<dealii::SymmetricTensor<4, 2>(std::size_t pixel)>
        &pixel_tensor);

    /**
     * Derivatives of the last homogenize()'s C^H with respect to n
     * parameters of the pixels' tensors, from dC/dq_m per pixel
     * (derivative[pixel][m]): 1/|Y| int eps(chi_a) : dC/dq_m : eps(chi_b)
     * (the cell problems are self-adjoint: no adjoint solve). Its error
     * follows the solver's tolerance (first order, unlike C^H's).
     */
    std::vector<dealii::SymmetricTensor<4, 2>>
    material_gradient(
      const std::vector<std::vector<dealii::SymmetricTensor<4, 2>>> &derivative)
      const;

    /// Levels of the multigrid hierarchy, finest first: cells along x, y.
    std::vector<std::array<unsigned int, 2>>
    levels() const;

    /**
     * Write the last homogenize()'s fluctuations w_11, w_22, w_12 (point
     * data) and cell data (cell_data[k][pixel], named cell_data_names[k])
     * to `file_stem`.vtu.
     */
    void
    write_vtu(const std::string                      &file_stem,
              const std::vector<std::string>         &cell_data_names,
              const std::vector<std::vector<double>> &cell_data) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace forma

#endif
