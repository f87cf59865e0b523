#include "plot_canvas.h"

#include <deal.II/base/exceptions.h>

#include <forma/base/replace_file.h>

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>

namespace forma
{
  namespace internal
  {
    namespace
    {
      // Cairo hands a surface's bytes to this callback as it produces them.
      cairo_status_t
      append(void *closure, const unsigned char *data, unsigned int length)
      {
        try // nothing may be thrown through Cairo's C code
          {
            static_cast<std::string *>(closure)->append(
              reinterpret_cast<const char *>(data), length);
            return CAIRO_STATUS_SUCCESS;
          }
        catch (...)
          {
            return CAIRO_STATUS_NO_MEMORY;
          }
      }
    } // namespace



    Canvas::Canvas(const std::string &file_name,
                   const double       width,
                   const double       height)
      : file_name(file_name)
      , format(std::filesystem::path(file_name).extension().string())
      , width(width)
      , height(height)
    {
      AssertThrow(format == ".png" || format == ".svg" || format == ".pdf",
                  dealii::ExcMessage("the plot '" + file_name +
                                     "' must end in .png, .svg or .pdf"));
      // Cairo's image surfaces end at 32767 pixels a side.
      AssertThrow(width >= 1 && height >= 1 && width < 32767 && height < 32767,
                  dealii::ExcMessage(
                    "the plot '" + file_name + "' would be " +
                    std::to_string(std::lround(width)) + " x " +
                    std::to_string(std::lround(height)) +
                    " units: empty, or over Cairo's 32767 a side"));
      if (format == ".png")
        surface =
          cairo_image_surface_create(CAIRO_FORMAT_RGB24,
                                     static_cast<int>(std::ceil(width)),
                                     static_cast<int>(std::ceil(height)));
      else if (format == ".svg")
        surface =
          cairo_svg_surface_create_for_stream(append, &bytes, width, height);
      else
        surface =
          cairo_pdf_surface_create_for_stream(append, &bytes, width, height);
      cr = cairo_create(surface);
      cairo_set_source_rgb(cr, 1, 1, 1);
      cairo_paint(cr);
      cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
      cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
      cairo_select_font_face(cr,
                             "DejaVu Sans",
                             CAIRO_FONT_SLANT_NORMAL,
                             CAIRO_FONT_WEIGHT_NORMAL);
    }



    Canvas::~Canvas()
    {
      cairo_destroy(cr);
      cairo_surface_destroy(surface);
    }



    void
    Canvas::set_color(const Color &color, const double alpha)
    {
      cairo_set_source_rgba(
        cr, color[0] / 255., color[1] / 255., color[2] / 255., alpha);
    }



    void
    Canvas::line(const Point &a, const Point &b, const double width)
    {
      stroke({a, b}, width);
    }



    void
    Canvas::stroke(const std::vector<Point> &points,
                   const double              width,
                   const bool                closed)
    {
      if (points.empty())
        return;
      cairo_new_path(cr);
      for (const Point &p : points)
        cairo_line_to(cr, p[0], p[1]);
      if (closed)
        cairo_close_path(cr);
      cairo_set_line_width(cr, width);
      cairo_stroke(cr);
    }



    void
    Canvas::fill(const std::vector<std::vector<Point>> &polygons)
    {
      cairo_new_path(cr);
      for (const auto &polygon : polygons)
        {
          cairo_new_sub_path(cr);
          for (const Point &p : polygon)
            cairo_line_to(cr, p[0], p[1]);
          cairo_close_path(cr);
        }
      cairo_set_fill_rule(cr, CAIRO_FILL_RULE_EVEN_ODD);
      cairo_fill(cr);
    }



    void
    Canvas::disc(const Point &center, const double radius)
    {
      cairo_new_path(cr);
      cairo_arc(cr, center[0], center[1], radius, 0, 2 * M_PI);
      cairo_fill(cr);
    }



    void
    Canvas::rectangle(const Point &lo, const Point &hi)
    {
      cairo_new_path(cr);
      cairo_rectangle(cr, lo[0], lo[1], hi[0] - lo[0], hi[1] - lo[1]);
      cairo_fill(cr);
    }



    void
    Canvas::image(const int                         width,
                  const int                         height,
                  const std::vector<unsigned char> &rgb,
                  const Point                      &corner,
                  const Point                      &extent)
    {
      cairo_surface_t *picture =
        cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
      if (cairo_surface_status(picture) != CAIRO_STATUS_SUCCESS)
        {
          cairo_surface_destroy(picture);
          AssertThrow(false,
                      dealii::ExcMessage("Cairo cannot hold a " +
                                         std::to_string(width) + " x " +
                                         std::to_string(height) +
                                         " image for '" + file_name + "'"));
        }
      cairo_surface_flush(picture);
      unsigned char *data   = cairo_image_surface_get_data(picture);
      const int      stride = cairo_image_surface_get_stride(picture);
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
          {
            const unsigned char *c = &rgb[3 * (std::size_t(y) * width + x)];
            reinterpret_cast<std::uint32_t *>(data + y * stride)[x] =
              (std::uint32_t(c[0]) << 16) | (std::uint32_t(c[1]) << 8) | c[2];
          }
      cairo_surface_mark_dirty(picture);
      cairo_save(cr);
      cairo_translate(cr, corner[0], corner[1]);
      if (extent[0] > 0 && extent[1] > 0)
        cairo_scale(cr, extent[0] / width, extent[1] / height);
      cairo_set_source_surface(cr, picture, 0, 0);
      // Grid cells as squares: no blending of neighbours (or of the
      // background at the edges) when scaled.
      cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
      cairo_paint(cr);
      cairo_restore(cr);
      cairo_surface_destroy(picture);
    }



    namespace
    {
      // Pieces of a label: plain text, and subscripts written "_x" (one
      // character) or "_{...}".
      std::vector<std::pair<std::string, bool>>
      pieces(const std::string &s)
      {
        std::vector<std::pair<std::string, bool>> p{{"", false}};
        for (std::size_t i = 0; i < s.size();)
          if (s[i] == '_' && i + 1 < s.size())
            {
              // The subscript is s[begin, end); plain text resumes at next.
              std::size_t       begin = i + 1, end, next;
              const std::size_t close = s.find('}', begin);
              if (s[begin] == '{' && close != std::string::npos)
                begin += 1, end = close, next = close + 1;
              else // one UTF-8 character
                {
                  end = begin + 1;
                  while (end < s.size() && (s[end] & 0xC0) == 0x80)
                    ++end;
                  next = end;
                }
              p.emplace_back(s.substr(begin, end - begin), true);
              p.emplace_back("", false);
              i = next;
            }
          else
            p.back().first += s[i++];
        return p;
      }
    } // namespace



    double
    Canvas::text_width(const std::string &s, const double size)
    {
      double w = 0;
      for (const auto &[piece, subscript] : pieces(s))
        {
          cairo_set_font_size(cr, subscript ? 0.7 * size : size);
          cairo_text_extents_t e;
          cairo_text_extents(cr, piece.c_str(), &e);
          w += e.x_advance;
        }
      return w;
    }



    void
    Canvas::text(const std::string &s,
                 const Point       &at,
                 const double       size,
                 const Anchor       anchor,
                 const bool         vertical)
    {
      const double w     = text_width(s, size);
      const double shift = anchor == Anchor::left   ? 0. :
                           anchor == Anchor::center ? -w / 2 :
                                                      -w;
      cairo_save(cr);
      cairo_translate(cr, at[0], at[1]);
      if (vertical)
        cairo_rotate(cr, -M_PI / 2);
      // DejaVu's digits and capitals are about 0.73 em tall.
      cairo_move_to(cr, shift, 0.36 * size);
      for (const auto &[piece, subscript] : pieces(s))
        {
          cairo_set_font_size(cr, subscript ? 0.7 * size : size);
          cairo_rel_move_to(cr, 0, subscript ? 0.25 * size : 0);
          cairo_show_text(cr, piece.c_str());
          cairo_rel_move_to(cr, 0, subscript ? -0.25 * size : 0);
        }
      cairo_restore(cr);
    }



    void
    Canvas::power_of_ten(const int exponent, const Point &at, const double size)
    {
      const std::string e     = std::to_string(exponent);
      const double      small = 0.72 * size;
      const double      w_e   = text_width(e, small);
      text(e, {{at[0], at[1] - 0.45 * size}}, small, Anchor::right);
      text("10", {{at[0] - w_e - 0.05 * size, at[1]}}, size, Anchor::right);
    }



    void
    Canvas::clip(const Point &lo, const Point &hi)
    {
      cairo_save(cr);
      cairo_new_path(cr);
      cairo_rectangle(cr, lo[0], lo[1], hi[0] - lo[0], hi[1] - lo[1]);
      cairo_clip(cr);
    }



    void
    Canvas::unclip()
    {
      cairo_restore(cr);
    }



    void
    Canvas::save()
    {
      // A drawing error (e.g. text that is not UTF-8) stops all drawing.
      AssertThrow(cairo_status(cr) == CAIRO_STATUS_SUCCESS,
                  dealii::ExcMessage(
                    "Cairo could not draw the plot '" + file_name +
                    "': " + cairo_status_to_string(cairo_status(cr))));
      if (format == ".png")
        {
          cairo_surface_flush(surface);
          AssertThrow(cairo_surface_write_to_png_stream(
                        surface, append, &bytes) == CAIRO_STATUS_SUCCESS,
                      dealii::ExcMessage("Cairo could not encode the plot '" +
                                         file_name + "'"));
        }
      else
        cairo_surface_finish(surface);
      const cairo_status_t status = cairo_surface_status(surface);
      AssertThrow(status == CAIRO_STATUS_SUCCESS,
                  dealii::ExcMessage("Cairo could not draw the plot '" +
                                     file_name +
                                     "': " + cairo_status_to_string(status)));
      replace_file(file_name, [&](const std::string &name) {
        std::ofstream out(name, std::ios::binary);
        out.write(bytes.data(), bytes.size());
        AssertThrow(out.flush(),
                    dealii::ExcMessage("cannot write the plot '" + file_name +
                                       "'"));
      });
    }



    Color
    color_scale(const double t)
    {
      const double stops[5][3] = {{40, 60, 200},
                                  {40, 190, 220},
                                  {60, 180, 60},
                                  {240, 210, 40},
                                  {210, 40, 30}};
      if (!std::isfinite(t))
        return {{200, 200, 200}}; // no value: gray
      const double s = 4 * std::clamp(t, 0., 1.);
      const int    k = std::min(3, static_cast<int>(s));
      Color        c;
      for (unsigned int i = 0; i < 3; ++i)
        c[i] = static_cast<std::uint8_t>(
          std::lround(stops[k][i] + (s - k) * (stops[k + 1][i] - stops[k][i])));
      return c;
    }
  } // namespace internal
} // namespace forma
