#include <forma/homogenization/bounds.h>
#include <forma/microstructure/hexagonal_laminate.h>
#include <forma/microstructure/pixel_material.h>

#include <algorithm>

namespace forma
{
  using namespace dealii;

  PixelMaterial::PixelMaterial(PhaseRaster                        raster,
                               std::vector<double>                phase_density,
                               std::vector<SymmetricTensor<4, 2>> phase_tensor,
                               const IsotropicModuli             &base,
                               const IsotropicModuli             &weak,
                               const GrayPixels                   gray)
    : raster(std::move(raster))
    , density(std::move(phase_density))
    , tensor(std::move(phase_tensor))
    , base(base)
    , weak(weak)
    , weak_tensor(weak.tensor())
    , gray(gray)
  {
    AssertThrow(density.size() == this->raster.n_phases &&
                  tensor.size() == this->raster.n_phases,
                ExcMessage("PixelMaterial: one density and one tensor per "
                           "raster phase"));
  }



  SymmetricTensor<4, 2>
  PixelMaterial::operator()(const Point<2> &x, const types::material_id) const
  {
    const auto [i, j] = raster.cell_of(x);
    SymmetricTensor<4, 2> C;
    double                rest = 1;
    for (unsigned int k = 1; k < raster.n_phases; ++k)
      {
        const double f = raster.fraction(i, j, k);
        C += f * tensor[k];
        rest -= f;
      }
    // Base material and void share the rest of the cell.
    rest = std::max(0., rest);
    if (rest <= 0)
      return C;
    const double rho = std::min(1., raster.fraction(i, j, 0) / rest);
    if (gray == GrayPixels::linear || rho <= 0 || rho >= 1)
      return C + rest * (rho * tensor[0] + (1 - rho) * weak_tensor);
    const auto b = hashin_shtrikman(base, weak, rho);
    return C +
           rest * IsotropicModuli::from_bulk_shear(b.kappa_upper, b.mu_upper)
                    .tensor();
  }



  double
  PixelMaterial::density_at(const Point<2> &x) const
  {
    const auto [i, j] = raster.cell_of(x);
    double rho        = 0;
    for (unsigned int k = 0; k < raster.n_phases; ++k)
      rho += density[k] * raster.fraction(i, j, k);
    return rho;
  }



  double
  PixelMaterial::volume_fraction() const
  {
    double phi = 0;
    for (unsigned int k = 0; k < raster.n_phases; ++k)
      phi += density[k] * raster.mean(k);
    return phi;
  }



  std::vector<SymmetricTensor<4, 2>>
  phase_tensors(const HexagonalLaminate &s,
                const IsotropicModuli   &base,
                const IsotropicModuli   &weak,
                std::vector<double>     &density)
  {
    density                                   = {1};
    std::vector<SymmetricTensor<4, 2>> tensor = {base.tensor()};
    if (s.limit)
      for (const double axis : s.joint_axis_angles())
        {
          density.push_back(s.theta);
          tensor.push_back(rank_one_laminate(base.tensor(),
                                             weak.tensor(),
                                             s.theta,
                                             axis + s.lamination_angle()));
        }
    return tensor;
  }



  PixelMaterial
  pixel_material(const HexagonalLaminate &s,
                 const IsotropicModuli   &base,
                 const IsotropicModuli   &weak,
                 const GrayPixels         gray,
                 const unsigned int       nx,
                 const unsigned int       ny)
  {
    std::vector<double> density;
    auto                tensor = phase_tensors(s, base, weak, density);
    return PixelMaterial(s.rasterize(nx, ny),
                         std::move(density),
                         std::move(tensor),
                         base,
                         weak,
                         gray);
  }
} // namespace forma
