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
   * @name Plots
   *
   * Drawn with Cairo: the file name's extension (.png, .svg or .pdf) picks
   * the format, labels are UTF-8 (Greek letters and subscripts work), and
   * every file is written whole or not at all. Each chart (x-y, polygon
   * field, overlay, field panels) leaves `<stem>.plot.csv` beside it with
   * exactly the plotted numbers, which `contrib/plot/redraw.py` turns back
   * into the chart (e.g. for a paper); images (write_image(),
   * write_level_set()) are their own data.
   */
  /** @{ */

  /**
   * A line plot of `values` against their index (iterations, time steps):
   * values / values[0] on a logarithmic axis when every value is positive,
   * the values on a linear one otherwise. `marks`: indices to mark with a
   * larger dot labelled `mark_label` (e.g. where outer iterations start).
   */
  void
  write_history_plot(const std::string               &file_name,
                     const std::vector<double>       &values,
                     const std::string               &title,
                     const std::string               &x_label,
                     const std::vector<unsigned int> &marks      = {},
                     const std::string               &mark_label = "");

  /// One data set of an x-y plot: points (discs of radius `size` + 0.5) or
  /// a polyline; an empty label keeps it out of the legend.
  struct PlotSeries
  {
    std::vector<std::array<double, 2>> points;
    std::array<std::uint8_t, 3>        color = {{31, 90, 180}};
    bool                               line  = false;
    int                                size  = 2;
    std::string                        label;
  };

  /// An x-y plot (points and lines, clipped to the ranges) with its legend
  /// beside the axes; `logarithmic` per axis (the range then positive):
  /// e.g. the (nu, E) coverage of a structure family against its
  /// Hashin-Shtrikman bounds.
  void
  write_xy_plot(const std::string             &file_name,
                const std::vector<PlotSeries> &series,
                const std::string             &title,
                const std::string             &x_label,
                const std::string             &y_label,
                const std::array<double, 2>   &x_range,
                const std::array<double, 2>   &y_range,
                const std::array<bool, 2>     &logarithmic = {{false, false}});

  /**
   * Polygons (mesh cells, in any units) filled by a value each (blue at
   * `range[0]` through green and yellow to red at `range[1]`), outlined in
   * gray, `width` units wide, with `title` on top and a color bar at the
   * right.
   */
  void
  write_polygon_field(
    const std::string                                     &file_name,
    const std::vector<std::vector<std::array<double, 2>>> &polygons,
    const std::vector<double>                             &values,
    const std::array<double, 2>                           &range,
    const std::string                                     &title,
    const int                                              width = 800);

  /**
   * Filled polygons (gray) with outlined ones (red) over them, in the
   * polygons' own units, `width` units wide: e.g. a deformed fine-scale
   * mesh with the deformed cells of its homogenized model.
   */
  void
  write_overlay(const std::string &file_name,
                const std::vector<std::vector<std::array<double, 2>>> &filled,
                const std::vector<std::vector<std::array<double, 2>>> &outlined,
                const int width = 1200);

  /// The material {phi < 0} of a level set (dark) over the box [lo, hi],
  /// sampled at `width` pixels across (a raster, also inside SVG or PDF).
  void
  write_level_set(const std::string                           &file_name,
                  const std::function<double(double, double)> &phi,
                  const std::array<double, 2>                 &lo,
                  const std::array<double, 2>                 &hi,
                  const int                                    width = 1200);

  /// One panel of write_field_panels(): a field on a regular grid, row by
  /// row from the top of the y range; `defined` (empty: everywhere) marks
  /// where it has a value (gray elsewhere).
  struct FieldPanel
  {
    std::string         title;
    std::vector<double> values;
    std::vector<bool>   defined;
  };

  /**
   * Fields on a common grid of `n_rows` x `n_columns` points over
   * [x_range] x [y_range], side by side in rows of `per_row` panels, each
   * colored blue to red over its own range (written under it): e.g. the
   * eight parameter surfaces of a material map (thesis Fig. 4.17).
   */
  void
  write_field_panels(const std::string             &file_name,
                     const std::vector<FieldPanel> &panels,
                     const unsigned int             n_rows,
                     const unsigned int             n_columns,
                     const std::array<double, 2>   &x_range,
                     const std::array<double, 2>   &y_range,
                     const std::string             &title,
                     const std::string             &x_label,
                     const std::string             &y_label,
                     const unsigned int             per_row = 4);

  /// An RGB image (rows from the top, 3 bytes per pixel).
  void
  write_image(const std::string                &file_name,
              const int                         width,
              const int                         height,
              const std::vector<unsigned char> &rgb);

  /** @} */
} // namespace forma

#endif
