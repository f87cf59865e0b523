#ifndef forma_laminate_study_h
#define forma_laminate_study_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/symmetric_tensor.h>

#include <forma/base/records.h>
#include <forma/homogenization/base_material.h>
#include <forma/homogenization/bounds.h>
#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/periodic_homogenization.h>
#include <forma/microstructure/hexagonal_laminate.h>
#include <forma/microstructure/pixel_material.h>

#include <nlohmann/json.hpp>

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
}

namespace forma
{
  class RunContext;

  /**
   * The forma-laminate application (thesis ch. 5) as library pieces: its
   * parameters, the homogenization of one Triangle/Hexagon structure on the
   * family grid, and the four modes (homogenize, sweep, inverse, compare
   * meshes), each in its own source file. New studies can reuse them.
   */
  namespace laminate
  {
    using forma::parse_values;
    using forma::sig;

    /// Base material, grid and solver: what every mode shares.
    struct Setup
    {
      BaseMaterial material;
      /// material.moduli() (parse_setup() sets both), and the void's (a weak
      /// phase, weak_ratio of them).
      IsotropicModuli                             base, weak;
      double                                      weak_ratio         = 1e-6;
      unsigned int                                cells_along_height = 148;
      PeriodicHomogenization<2>::SolverParameters solver;
      bool                                        write_vtu = true;
      GrayPixels gray     = GrayPixels::hashin_shtrikman;
      bool       symmetry = true;
      /// Structures with thinner beams, gaps or joints are under-resolved.
      double min_feature_cells = 3;
      /// Family structures are isotropic: a larger isotropy residual is
      /// discretization error.
      double isotropy_tolerance = 0.05;
      /// homogenize: refinement cycles of the grid, and the fraction of the
      /// cells refined in each.
      unsigned int adaptive_cycles = 0;
      double       refine_fraction = 0.2;
    };

    /// What one homogenized structure gives.
    struct Sample
    {
      double                        phi = 0, phi_formula = 0;
      dealii::SymmetricTensor<4, 2> C;
      IsotropicModuli               fit;
      Anisotropy                    anisotropy;
      HashinShtrikmanBounds         hs;
      double                        hs_violation = 0;
    };

    /// Homogenize `material` on `cell`: C^H, isotropic fit, anisotropy, HS
    /// bounds at the measured volume fraction.
    Sample
    evaluate(PeriodicHomogenization<2> &cell,
             const PixelMaterial       &material,
             const Setup               &setup);

    /// Exact derivatives of a Sample with respect to the structure's
    /// continuous parameters (HexagonalLaminate::continuous_parameters(),
    /// alpha in radians).
    struct SampleGradient
    {
      std::array<dealii::SymmetricTensor<4, 2>, HexagonalLaminate::n_continuous>
                                                          C;
      std::array<double, HexagonalLaminate::n_continuous> E, nu;
    };

    /**
     * The gradient of `sample`, the last homogenization on `cell` of
     * `structure` rasterized on nx x ny pixels: the pixel tensors'
     * derivatives (PixelMaterialGradient) through C^H's material gradient
     * (no adjoint solve) and the isotropic fit.
     */
    SampleGradient
    evaluate_gradient(const PeriodicHomogenization<2> &cell,
                      const HexagonalLaminate         &structure,
                      const Setup                     &setup,
                      const unsigned int               nx,
                      const unsigned int               ny,
                      const Sample                    &sample);

    /// Cells along the sqrt(3) x 1 rectangle for ny along its height: the
    /// even number nearest sqrt(3) ny.
    unsigned int
    grid_nx(const unsigned int ny);

    /**
     * The homogenization grid of the family structures on ny cells along
     * the height. With Setup::symmetry: the primitive half of the rectangle
     * (ny even) and odd fluctuations: the rectangle's C^H with a quarter
     * of the unknowns.
     */
    std::unique_ptr<PeriodicHomogenization<2>>
    family_grid(const MPI_Comm comm, const Setup &setup, const unsigned int ny);

    /// The Structure section (range-checked).
    HexagonalLaminate
    read_structure(dealii::ParameterHandler &prm);

    nlohmann::json
    structure_json(const HexagonalLaminate &s);

    /// C_voigt, moduli, anisotropy, HS bounds and CLM moduli of a sample.
    nlohmann::json
    sample_json(const Sample &r, const Setup &setup);

    /// The Sweep section: families and a parameter grid.
    struct SweepGrid
    {
      std::vector<HexagonalLaminate::Family>     families;
      bool                                       limit = false;
      std::map<std::string, std::vector<double>> values;
      std::vector<HexagonalLaminate>             structures;
      double                                     level = 0.5, band = 0.02;
    };


    /// The Sweep section's families and parameter grid (range-checked).
    SweepGrid
    read_sweep_grid(dealii::ParameterHandler &prm);

    /// Columns of the sample table (after the structure parameters).
    constexpr unsigned int n_fields = 15;
    enum Field
    {
      f_phi_formula,
      f_phi,
      f_E,
      f_nu,
      f_kappa,
      f_mu,
      f_a1,
      f_a2,
      f_residual,
      f_hs_violation,
      f_C00,
      f_C01,
      f_C11,
      f_C22,
      f_min_feature_cells
    };


    class SweepProgress;

    /**
     * Homogenize `structures` on the family grid with ny cells along the
     * height, round-robin over the ranks of `context` (each with its own
     * serial solver), with a progress line per batch. Returns n_fields
     * values per structure on every rank. With a `progress` file, the
     * structures it holds are taken over and every batch is appended to it.
     */
    std::vector<double>
    homogenize_all(const std::vector<HexagonalLaminate> &structures,
                   const Setup                          &setup,
                   const unsigned int                    ny,
                   RunContext                           &context,
                   const SweepProgress                  *progress = nullptr);

    /// Every section and entry of the application's parameter file.
    void
    declare_parameters(dealii::ParameterHandler &prm);

    /// Setup from the Base material, Grid and Output sections (recorded in
    /// the summary).
    Setup
    parse_setup(dealii::ParameterHandler &prm, RunContext &context);
  } // namespace laminate
} // namespace forma

#endif
