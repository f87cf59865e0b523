#ifndef forma_source_microstructure_polygon_raster_h
#define forma_source_microstructure_polygon_raster_h

// Convex polygons and their anti-aliased rasterization for any scalar:
// double, or a forward AD number whose derivatives are those of the exact
// areas (internal, not installed; used by raster.cc, hexagonal_laminate.cc
// and pixel_material.cc).

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/differentiation/ad/sacado_product_types.h>

#include <Sacado.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace forma
{
  namespace internal
  {
    template <typename Number>
    using Polygon = std::vector<dealii::Point<2, Number>>;

    template <typename Number>
    double
    value(const Number &x)
    {
      return Sacado::ScalarValue<Number>::eval(x);
    }

    /// Signed area (positive for counterclockwise vertices).
    template <typename Number>
    Number
    polygon_area(const Polygon<Number> &polygon)
    {
      Number a = 0;
      for (unsigned int k = 0; k < polygon.size(); ++k)
        {
          const auto &p = polygon[k], &q = polygon[(k + 1) % polygon.size()];
          a += p[0] * q[1] - q[0] * p[1];
        }
      return a / 2.;
    }

    /// The part of `polygon` where (x - point) . normal <= 0
    /// (Sutherland-Hodgman against one half plane; the branches follow the
    /// values, the new vertices carry the derivatives).
    template <typename Number>
    Polygon<Number>
    clip_polygon(const Polygon<Number>              &polygon,
                 const dealii::Point<2, Number>     &point,
                 const dealii::Tensor<1, 2, Number> &normal)
    {
      Polygon<Number> result;
      result.reserve(polygon.size() + 1);
      for (unsigned int k = 0; k < polygon.size(); ++k)
        {
          const auto  &p = polygon[k], &q = polygon[(k + 1) % polygon.size()];
          const Number dp = (p - point) * normal, dq = (q - point) * normal;
          const double vp = value(dp), vq = value(dq);
          if (vp <= 0)
            result.push_back(p);
          if ((vp < 0 && vq > 0) || (vp > 0 && vq < 0))
            {
              const Number t = dp / (dp - dq);
              result.push_back(p + t * (q - p));
            }
        }
      return result.size() >= 3 ? result : Polygon<Number>();
    }

    /// The regular nx x ny grid of [0, width] x [0, height] with n_phases
    /// fractions per cell, stored as fractions[(j nx + i) n_phases + phase].
    struct RasterGrid
    {
      unsigned int nx, ny, n_phases;
      double       width, height;
    };

    /// Add the fractions of the grid cells covered by `polygon` to `phase`.
    template <typename Number>
    void
    rasterize_polygon(const Polygon<Number> &polygon,
                      const unsigned int     phase,
                      const RasterGrid      &grid,
                      std::vector<Number>   &fractions)
    {
      if (polygon.size() < 3)
        return;
      const double hx = grid.width / grid.nx, hy = grid.height / grid.ny;
      double       x0 = value(polygon[0][0]), x1 = x0;
      double       y0 = value(polygon[0][1]), y1 = y0;
      for (const auto &p : polygon)
        {
          x0 = std::min(x0, value(p[0]));
          x1 = std::max(x1, value(p[0]));
          y0 = std::min(y0, value(p[1]));
          y1 = std::max(y1, value(p[1]));
        }
      const int i0 = std::max(0, static_cast<int>(std::floor(x0 / hx)));
      const int i1 =
        std::min<int>(grid.nx - 1, static_cast<int>(std::floor(x1 / hx)));
      const int j0 = std::max(0, static_cast<int>(std::floor(y0 / hy)));
      const int j1 =
        std::min<int>(grid.ny - 1, static_cast<int>(std::floor(y1 / hy)));
      using P = dealii::Point<2, Number>;
      using T = dealii::Tensor<1, 2, Number>;
      T ex, ey;
      ex[0] = 1;
      ey[1] = 1;
      for (int j = j0; j <= j1; ++j)
        {
          // Clip to the row first, then to each cell of it.
          Polygon<Number> row =
            clip_polygon(polygon, P(Number(0), Number(j * hy)), -ey);
          row = clip_polygon(row, P(Number(0), Number((j + 1) * hy)), ey);
          if (row.empty())
            continue;
          for (int i = i0; i <= i1; ++i)
            {
              Polygon<Number> cell =
                clip_polygon(row, P(Number(i * hx), Number(0)), -ex);
              cell = clip_polygon(cell, P(Number((i + 1) * hx), Number(0)), ex);
              if (!cell.empty())
                fractions[(static_cast<std::size_t>(j) * grid.nx + i) *
                            grid.n_phases +
                          phase] += polygon_area(cell) / (hx * hy);
            }
        }
    }
  } // namespace internal
} // namespace forma

#endif
