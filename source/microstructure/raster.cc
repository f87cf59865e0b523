#include <deal.II/base/exceptions.h>

#include <forma/microstructure/raster.h>

#include <algorithm>
#include <cmath>

namespace forma
{
  using namespace dealii;

  double
  area(const ConvexPolygon &polygon)
  {
    double a = 0;
    for (unsigned int k = 0; k < polygon.size(); ++k)
      {
        const Point<2> &p = polygon[k], &q = polygon[(k + 1) % polygon.size()];
        a += p[0] * q[1] - q[0] * p[1];
      }
    return a / 2;
  }



  ConvexPolygon
  clip(const ConvexPolygon &polygon,
       const Point<2>      &point,
       const Tensor<1, 2>  &normal)
  {
    // Sutherland-Hodgman against one half plane.
    ConvexPolygon result;
    result.reserve(polygon.size() + 1);
    for (unsigned int k = 0; k < polygon.size(); ++k)
      {
        const Point<2> &p = polygon[k], &q = polygon[(k + 1) % polygon.size()];
        const double    dp = (p - point) * normal, dq = (q - point) * normal;
        if (dp <= 0)
          result.push_back(p);
        if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0))
          result.push_back(p + (dp / (dp - dq)) * (q - p));
      }
    return result.size() >= 3 ? result : ConvexPolygon();
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
    if (polygon.size() < 3)
      return;
    const double hx = width / nx, hy = height / ny;
    double       x0 = polygon[0][0], x1 = x0, y0 = polygon[0][1], y1 = y0;
    for (const auto &p : polygon)
      {
        x0 = std::min(x0, p[0]);
        x1 = std::max(x1, p[0]);
        y0 = std::min(y0, p[1]);
        y1 = std::max(y1, p[1]);
      }
    const int i0 = std::max(0, static_cast<int>(std::floor(x0 / hx)));
    const int i1 = std::min<int>(nx - 1, static_cast<int>(std::floor(x1 / hx)));
    const int j0 = std::max(0, static_cast<int>(std::floor(y0 / hy)));
    const int j1 = std::min<int>(ny - 1, static_cast<int>(std::floor(y1 / hy)));
    const Tensor<1, 2> ex({1., 0.}), ey({0., 1.});
    for (int j = j0; j <= j1; ++j)
      {
        // Clip to the row first, then to each cell of it.
        ConvexPolygon row = clip(polygon, Point<2>(0, j * hy), -ey);
        row               = clip(row, Point<2>(0, (j + 1) * hy), ey);
        if (row.empty())
          continue;
        for (int i = i0; i <= i1; ++i)
          {
            ConvexPolygon cell = clip(row, Point<2>(i * hx, 0), -ex);
            cell               = clip(cell, Point<2>((i + 1) * hx, 0), ex);
            if (!cell.empty())
              fractions[(static_cast<std::size_t>(j) * nx + i) * n_phases +
                        phase] += area(cell) / (hx * hy);
          }
      }
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
