#ifndef forma_base_plot_h
#define forma_base_plot_h

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace forma
{
  /**
   * Write a PNG line plot of `values` against their index (iterations, time
   * steps): a logarithmic y axis of values / values[0] when every value is
   * positive, a linear one otherwise. Small and dependency-free apart from
   * zlib, so every app can leave a picture of its convergence next to its
   * numbers.
   */
  void
  write_history_plot(const std::string         &file_name,
                     const std::vector<double> &values,
                     const std::string         &title,
                     const std::string         &x_label);

  /// One data set of an x-y plot: points (dots of half-size `size`) or a
  /// polyline; an empty label keeps it out of the legend.
  struct PlotSeries
  {
    std::vector<std::array<double, 2>> points;
    std::array<std::uint8_t, 3>        color = {{31, 90, 180}};
    bool                               line  = false;
    int                                size  = 2;
    std::string                        label;
  };

  /// Write a PNG x-y plot (scatter and lines) over the given ranges, with a
  /// legend; e.g. the (nu, E) coverage of a structure family against its
  /// Hashin-Shtrikman bounds.
  void
  write_xy_plot(const std::string             &file_name,
                const std::vector<PlotSeries> &series,
                const std::string             &title,
                const std::string             &x_label,
                const std::string             &y_label,
                const std::array<double, 2>   &x_range,
                const std::array<double, 2>   &y_range);

  /**
   * A picture of polygons (mesh cells, in any units) filled by a value each
   * (blue at `range[0]` through green and yellow to red at `range[1]`),
   * outlined in gray, `width` pixels wide, with `title` on top and a color
   * bar with the range at the right.
   */
  void
  write_polygon_field_png(
    const std::string                                     &file_name,
    const std::vector<std::vector<std::array<double, 2>>> &polygons,
    const std::vector<double>                             &values,
    const std::array<double, 2>                           &range,
    const std::string                                     &title,
    const int                                              width = 800);

  /**
   * Filled polygons (gray) with outlined ones (red) over them, in the
   * polygons' own units, `width` pixels wide: e.g. a deformed fine-scale
   * mesh with the deformed cells of its homogenized model.
   */
  void
  write_overlay_png(
    const std::string                                     &file_name,
    const std::vector<std::vector<std::array<double, 2>>> &filled,
    const std::vector<std::vector<std::array<double, 2>>> &outlined,
    const int                                              width = 1200);

  /**
   * Closed polygons (outer boundaries and holes alike, filled by the
   * even-odd rule) as one SVG path, y up, one unit a millimetre, with a
   * stroke of `stroke` units: e.g. a microstructured object's outline for
   * a laser cutter.
   */
  void
  write_polygons_svg(
    const std::string                                     &file_name,
    const std::vector<std::vector<std::array<double, 2>>> &polygons,
    const double                                           stroke);

  /// The material {phi < 0} of a level set (dark) over the box [lo, hi],
  /// `width` pixels wide.
  void
  write_level_set_png(const std::string                           &file_name,
                      const std::function<double(double, double)> &phi,
                      const std::array<double, 2>                 &lo,
                      const std::array<double, 2>                 &hi,
                      const int width = 1200);

  /// Write an RGB image (rows from the top, 3 bytes per pixel) as PNG.
  void
  write_image_png(const std::string                &file_name,
                  const int                         width,
                  const int                         height,
                  const std::vector<unsigned char> &rgb);
} // namespace forma

#endif
