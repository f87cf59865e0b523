#include <forma/homogenization/bounds.h>
#include <forma/microstructure/hexagonal_laminate.h>
#include <forma/microstructure/pixel_material.h>

#include "laminate_polygons.h"
#include <Sacado.hpp>
#include <boost/container/small_vector.hpp>

#include <algorithm>

namespace forma
{
  using namespace dealii;

  namespace
  {
    using AD = Sacado::Fad::DFad<double>;

    /**
     * The tensor of a grid cell with phase fractions f: phases 1.. by their
     * fractions, the rest shared by base material (phase 0, density rho)
     * and void, mixed by `gray`. For double or AD fractions and tensors.
     */
    template <typename Number>
    SymmetricTensor<4, 2, Number>
    mixed_tensor(const Number                                     *f,
                 const std::vector<SymmetricTensor<4, 2, Number>> &tensor,
                 const IsotropicModuli                            &base,
                 const IsotropicModuli                            &weak,
                 const GrayPixels                                  gray)
    {
      SymmetricTensor<4, 2, Number> C;
      Number                        rest = 1;
      for (unsigned int k = 1; k < tensor.size(); ++k)
        {
          C += f[k] * tensor[k];
          rest -= f[k];
        }
      if (internal::value(rest) <= 0)
        return C;
      Number rho = f[0] / rest;
      if (internal::value(rho) >= 1)
        rho = 1;
      const SymmetricTensor<4, 2, Number> weak_tensor =
        isotropic_tensor(Number(weak.kappa), Number(weak.mu));
      if (gray == GrayPixels::linear || internal::value(rho) <= 0 ||
          internal::value(rho) >= 1)
        {
          const Number void_part = 1. - rho;
          return C + rest * (rho * tensor[0] + void_part * weak_tensor);
        }
      const auto [kappa, mu] = hashin_shtrikman_upper(base, weak, rho);
      return C + rest * isotropic_tensor(kappa, mu);
    }

    /// phase_tensors() with the continuous parameters q.
    template <typename Number>
    std::vector<SymmetricTensor<4, 2, Number>>
    phase_tensors_of(
      const HexagonalLaminate                                   &s,
      const std::array<Number, HexagonalLaminate::n_continuous> &q,
      const IsotropicModuli                                     &base,
      const IsotropicModuli                                     &weak,
      std::vector<double>                                       &density)
    {
      const SymmetricTensor<4, 2, Number> strong =
        isotropic_tensor(Number(base.kappa), Number(base.mu));
      density                                           = {1};
      std::vector<SymmetricTensor<4, 2, Number>> tensor = {strong};
      if (s.limit)
        for (const double axis : s.joint_axis_angles())
          {
            density.push_back(s.theta);
            const Number angle = axis + q[2];
            tensor.push_back(rank_one_laminate(
              strong,
              isotropic_tensor(Number(weak.kappa), Number(weak.mu)),
              q[1],
              angle));
          }
      return tensor;
    }
  } // namespace

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
    // No allocation per cell: a grid holds few phases.
    boost::container::small_vector<double, 8> f(raster.n_phases);
    for (unsigned int k = 0; k < raster.n_phases; ++k)
      f[k] = raster.fraction(i, j, k);
    return mixed_tensor(f.data(), tensor, base, weak, gray);
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
    return phase_tensors_of(s, s.continuous_parameters(), base, weak, density);
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



  PixelMaterialGradient::PixelMaterialGradient(const HexagonalLaminate &s,
                                               const IsotropicModuli   &base,
                                               const IsotropicModuli   &weak,
                                               const GrayPixels         gray,
                                               const unsigned int       nx,
                                               const unsigned int       ny)
    : grid(nx, ny, HexagonalLaminate::width, HexagonalLaminate::height, 1)
    , derivative(static_cast<std::size_t>(nx) * ny)
  {
    s.check();
    constexpr unsigned int n      = HexagonalLaminate::n_continuous;
    const auto             values = s.continuous_parameters();
    std::array<AD, n>      q;
    for (unsigned int m = 0; m < n; ++m)
      q[m] = AD(n, m, values[m]);
    const unsigned int n_phases = s.limit ? 4 : 1;
    std::vector<AD>    fractions(derivative.size() * n_phases, AD(0.));
    for (const auto &[polygon, phase] : internal::structure_polygons(s, q))
      internal::rasterize_polygon(polygon,
                                  phase,
                                  {nx, ny, n_phases, grid.width, grid.height},
                                  fractions);
    std::vector<double> density;
    const auto          tensor = phase_tensors_of(s, q, base, weak, density);
    for (std::size_t c = 0; c < derivative.size(); ++c)
      {
        const SymmetricTensor<4, 2, AD> C =
          mixed_tensor(&fractions[c * n_phases], tensor, base, weak, gray);
        for (unsigned int m = 0; m < n; ++m)
          for (unsigned int i = 0; i < 2; ++i)
            for (unsigned int j = i; j < 2; ++j)
              for (unsigned int k = 0; k < 2; ++k)
                for (unsigned int l = k; l < 2; ++l)
                  derivative[c][m][i][j][k][l] =
                    C[i][j][k][l].size() > 0 ? C[i][j][k][l].dx(m) : 0.;
      }
  }



  const PixelMaterialGradient::Derivatives &
  PixelMaterialGradient::operator()(const Point<2> &x) const
  {
    const auto [i, j] = grid.cell_of(x);
    return derivative[static_cast<std::size_t>(j) * grid.nx + i];
  }
} // namespace forma
