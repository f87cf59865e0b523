#ifndef forma_base_plot_canvas_h
#define forma_base_plot_canvas_h

// Internal to plot.cc and its tests' subject: a drawing surface on Cairo,
// the same code for PNG, SVG and PDF, written whole or not at all.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

typedef struct _cairo         cairo_t;
typedef struct _cairo_surface cairo_surface_t;

namespace forma
{
  namespace internal
  {
    using Color = std::array<std::uint8_t, 3>;
    using Point = std::array<double, 2>;

    /// Horizontal anchor of a text: its left end, center or right end.
    enum class Anchor
    {
      left,
      center,
      right
    };

    /**
     * A white canvas of `width` x `height` units (pixels for PNG, points for
     * SVG and PDF, chosen by the file name's extension) with y down.
     * `save()` writes the file atomically; a canvas destroyed unsaved writes
     * nothing.
     */
    class Canvas
    {
    public:
      Canvas(const std::string &file_name,
             const double       width,
             const double       height);
      ~Canvas();
      Canvas(const Canvas &) = delete;
      Canvas &
      operator=(const Canvas &) = delete;

      void
      set_color(const Color &color, const double alpha = 1.);

      void
      line(const Point &a, const Point &b, const double width);

      /// An open polyline (`closed` = false) or a closed polygon's outline.
      void
      stroke(const std::vector<Point> &points,
             const double              width,
             const bool                closed = false);

      /// Polygons filled together by the even-odd rule (holes as loops).
      void
      fill(const std::vector<std::vector<Point>> &polygons);

      void
      disc(const Point &center, const double radius);

      void
      rectangle(const Point &lo, const Point &hi);

      /// Text in DejaVu Sans (UTF-8: Greek letters work) of `size` units,
      /// vertically centered on `at`; `vertical` text reads upwards.
      void
      text(const std::string &s,
           const Point       &at,
           const double       size,
           const Anchor       anchor   = Anchor::left,
           const bool         vertical = false);

      /// An RGB image (rows from the top, 3 bytes a pixel), its top left
      /// corner at `corner`, `extent` units wide and high (zero: one unit
      /// a pixel).
      void
      image(const int                         width,
            const int                         height,
            const std::vector<unsigned char> &rgb,
            const Point                      &corner = {{0, 0}},
            const Point                      &extent = {{0, 0}});

      /// "10" with a raised exponent, its right end at `at`.
      void
      power_of_ten(const int exponent, const Point &at, const double size);

      double
      text_width(const std::string &s, const double size);

      /// Restrict drawing to a rectangle until `unclip()`.
      void
      clip(const Point &lo, const Point &hi);

      void
      unclip();

      void
      save();

    private:
      std::string      file_name;
      std::string      format;
      double           width, height;
      std::string      bytes;
      cairo_surface_t *surface;
      cairo_t         *cr;
    };

    /// blue (t = 0) through cyan, green and yellow to red (t = 1).
    Color
    color_scale(const double t);
  } // namespace internal
} // namespace forma

#endif
