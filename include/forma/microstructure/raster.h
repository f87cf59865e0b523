#ifndef forma_microstructure_raster_h
#define forma_microstructure_raster_h

#include <deal.II/base/point.h>

#include <vector>

namespace forma
{
  /// A convex polygon, vertices counterclockwise.
  using ConvexPolygon = std::vector<dealii::Point<2>>;

  /// Signed area (positive for counterclockwise vertices).
  double
  area(const ConvexPolygon &polygon);

  /// The part of `polygon` where (x - point) . normal <= 0.
  ConvexPolygon
  clip(const ConvexPolygon        &polygon,
       const dealii::Point<2>     &point,
       const dealii::Tensor<1, 2> &normal);

  /**
   * Fractions of the cells of a regular nx x ny grid on [0, W] x [0, H]
   * covered by phases of convex polygons: anti-aliased rasterization by
   * exact areas (thesis ch. 5.4). Polygons of one phase must not overlap;
   * their parts outside the box are ignored (periodic structures pass their
   * periodic images).
   */
  class PhaseRaster
  {
  public:
    PhaseRaster(const unsigned int nx,
                const unsigned int ny,
                const double       width,
                const double       height,
                const unsigned int n_phases);

    void
    add(const ConvexPolygon &polygon, const unsigned int phase);

    /// Covered fraction of cell (i, j) (i along x) by `phase`.
    double
    fraction(const unsigned int i,
             const unsigned int j,
             const unsigned int phase) const
    {
      return fractions[(j * nx + i) * n_phases + phase];
    }

    /// The cell containing point p (clamped to the grid).
    std::pair<unsigned int, unsigned int>
    cell_of(const dealii::Point<2> &p) const;

    /// Area fraction of the box covered by `phase`.
    double
    mean(const unsigned int phase) const;

    unsigned int nx, ny, n_phases;
    double       width, height;

  private:
    std::vector<double> fractions;
  };
} // namespace forma

#endif
