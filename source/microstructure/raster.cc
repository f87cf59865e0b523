#include <deal.II/base/exceptions.h>

#include <forma/microstructure/raster.h>

#include "polygon_raster.h"

#include <algorithm>
#include <cmath>

namespace forma
{
  using namespace dealii;

  double
  area(const ConvexPolygon &polygon)
  {
    return internal::polygon_area(polygon);
  }



  ConvexPolygon
  clip(const ConvexPolygon &polygon,
       const Point<2>      &point,
       const Tensor<1, 2>  &normal)
  {
    return internal::clip_polygon(polygon, point, normal);
  }



  PhaseRaster::PhaseRaster(const unsigned int nx,
                           const unsigned int ny,
                           const double       width,
                           const double       height,
                           const unsigned int n_phases)
    : nx(nx)
    , ny(ny)
    , n_phases(n_phases)
    , width(width)
    , height(height)
    , fractions(static_cast<std::size_t>(nx) * ny * n_phases, 0.)
  {
    AssertThrow(nx > 0 && ny > 0 && width > 0 && height > 0,
                ExcMessage("a raster needs a positive size"));
  }



  void
  PhaseRaster::add(const ConvexPolygon &polygon, const unsigned int phase)
  {
    AssertThrow(phase < n_phases, ExcMessage("raster phase out of range"));
    internal::rasterize_polygon(polygon,
                                phase,
                                {nx, ny, n_phases, width, height},
                                fractions);
  }



  std::pair<unsigned int, unsigned int>
  PhaseRaster::cell_of(const Point<2> &p) const
  {
    const int i = static_cast<int>(std::floor(p[0] / width * nx));
    const int j = static_cast<int>(std::floor(p[1] / height * ny));
    return {static_cast<unsigned int>(std::clamp<int>(i, 0, nx - 1)),
            static_cast<unsigned int>(std::clamp<int>(j, 0, ny - 1))};
  }



  double
  PhaseRaster::mean(const unsigned int phase) const
  {
    double sum = 0;
    for (std::size_t k = phase; k < fractions.size(); k += n_phases)
      sum += fractions[k];
    return sum / (static_cast<double>(nx) * ny);
  }
} // namespace forma
