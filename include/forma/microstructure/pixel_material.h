#ifndef forma_microstructure_pixel_material_h
#define forma_microstructure_pixel_material_h

#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/types.h>

#include <forma/homogenization/elastic_tensor.h>
#include <forma/microstructure/hexagonal_laminate.h>
#include <forma/microstructure/raster.h>

#include <array>
#include <vector>

namespace forma
{
  /// How a grid cell partly covered by base material (fraction rho) mixes
  /// it with the void (weak) phase.
  enum class GrayPixels
  {
    /// rho C (thesis eq. 5.8): the Voigt bound, so under-resolved gaps can
    /// make a result exceed the HS bounds.
    linear,
    /// The HS upper bound at rho (eq. 5.1): the stiffest physical mixture,
    /// so results stay attainable.
    hashin_shtrikman
  };

  /**
   * The material of a regular homogenization grid from a phase raster:
   * phase k covers fraction f_k of a cell and has tensor C_k and base
   * material density rho_k (1 for solid, theta for a laminate). Phase 0 is
   * the base material, the uncovered rest of a cell is void (a weak
   * isotropic phase); base and void in one cell mix by `gray`. A
   * PeriodicHomogenization::MaterialFunction.
   */
  class PixelMaterial
  {
  public:
    PixelMaterial(PhaseRaster                                raster,
                  std::vector<double>                        phase_density,
                  std::vector<dealii::SymmetricTensor<4, 2>> phase_tensor,
                  const IsotropicModuli                     &base,
                  const IsotropicModuli                     &weak,
                  const GrayPixels                           gray);

    dealii::SymmetricTensor<4, 2>
    operator()(const dealii::Point<2> &x,
               const dealii::types::material_id) const;

    /// Base-material density of the cell holding x.
    double
    density_at(const dealii::Point<2> &x) const;

    /// Base-material volume fraction of the whole cell.
    double
    volume_fraction() const;

    const PhaseRaster &
    phase_raster() const
    {
      return raster;
    }

  private:
    PhaseRaster                                raster;
    std::vector<double>                        density;
    std::vector<dealii::SymmetricTensor<4, 2>> tensor;
    IsotropicModuli                            base, weak;
    GrayPixels                                 gray;
  };

  /**
   * The phases of a Triangle/Hexagon structure in the order of
   * HexagonalLaminate::polygons(): the base material, then (limit
   * structures) the rank-one laminates of the three joints (eq. 5.9) with
   * the void as their weak phase. Densities in `density`.
   */
  std::vector<dealii::SymmetricTensor<4, 2>>
  phase_tensors(const HexagonalLaminate &structure,
                const IsotropicModuli   &base,
                const IsotropicModuli   &weak,
                std::vector<double>     &density);

  /// A structure rasterized on an nx x ny grid of its cell.
  PixelMaterial
  pixel_material(const HexagonalLaminate &structure,
                 const IsotropicModuli   &base,
                 const IsotropicModuli   &weak,
                 const GrayPixels         gray,
                 const unsigned int       nx,
                 const unsigned int       ny);

  /**
   * The exact derivatives of pixel_material()'s cell tensors with respect
   * to the structure's continuous parameters
   * (HexagonalLaminate::continuous_parameters(), alpha in radians): forward
   * AD through the polygons, their exact areas in every grid cell (the
   * derivative of a covered area is the flux of the boundary's velocity
   * through the cell), the laminate phases and the gray-pixel mixing. The
   * map is piecewise smooth: a derivative jumps where a polygon edge
   * crosses a grid line along itself or a beam appears.
   */
  class PixelMaterialGradient
  {
  public:
    using Derivatives = std::array<dealii::SymmetricTensor<4, 2>,
                                   HexagonalLaminate::n_continuous>;

    PixelMaterialGradient(const HexagonalLaminate &structure,
                          const IsotropicModuli   &base,
                          const IsotropicModuli   &weak,
                          const GrayPixels         gray,
                          const unsigned int       nx,
                          const unsigned int       ny);

    /// dC/dq of the grid cell holding x.
    const Derivatives &
    operator()(const dealii::Point<2> &x) const;

  private:
    PhaseRaster              grid;
    std::vector<Derivatives> derivative;
  };
} // namespace forma

#endif
