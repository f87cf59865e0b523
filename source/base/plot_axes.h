#ifndef forma_base_plot_axes_h
#define forma_base_plot_axes_h

// Internal to plot.cc: linear and logarithmic axes, and the framed plot
// area (grid, ticks, labels, title) that the x-y plots share.

#include "plot_canvas.h"

#include <string>
#include <vector>

namespace forma
{
  namespace internal
  {
    /// One axis: its range and scale; ticks at "nice" values or decades.
    struct Axis
    {
      double lo, hi;
      bool   logarithmic;
      /// Ticks at whole numbers only (a linear axis of counts).
      bool whole;

      /// Where `v` sits along the axis, 0 at `lo` and 1 at `hi`.
      double
      unit(const double v) const;

      /// Labelled ticks.
      std::vector<double>
      ticks() const;

      /// Unlabelled ticks between the decades of a logarithmic axis.
      std::vector<double>
      minor_ticks() const;
    };

    /// The rectangle [left, right] x [top, bottom] of the canvas that shows
    /// the data, and its two axes.
    struct Frame
    {
      double left, right, top, bottom;
      Axis   x, y;

      Point
      at(const double xv, const double yv) const;

      Point
      at(const Point &p) const
      {
        return at(p[0], p[1]);
      }
    };

    /// Grid, ticks and tick labels of both axes, the axes' labels, and the
    /// title centered over the canvas's `width`.
    void
    draw_frame(Canvas            &canvas,
               const Frame       &frame,
               const double       width,
               const std::string &title,
               const std::string &x_label,
               const std::string &y_label);

    /// `v` with three significant digits.
    std::string
    tick_label(const double v);
  } // namespace internal
} // namespace forma

#endif
