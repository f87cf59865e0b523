#include <deal.II/base/exceptions.h>

#include <forma/base/plot.h>

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

namespace forma
{
  namespace
  {
    // A 5x7 bitmap font for the characters the plots use.
    const std::map<char, std::array<std::uint8_t, 7>> &
    font()
    {
      static const std::map<char, std::array<std::uint8_t, 7>> glyphs = {
        {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
        {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
        {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
        {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
        {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
        {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
        {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
        {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
        {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
        {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
        {'.', {0, 0, 0, 0, 0, 0x0C, 0x0C}},
        {'-', {0, 0, 0, 0x1F, 0, 0, 0}},
        {'+', {0, 0x04, 0x04, 0x1F, 0x04, 0x04, 0}},
        {'/', {0, 0x01, 0x02, 0x04, 0x08, 0x10, 0}},
        {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}},
        {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
        {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
        {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
        {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}},
        {'D', {0x1E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1E}},
        {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}},
        {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
        {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}},
        {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
        {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}},
        {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
        {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}},
        {'N', {0x11, 0x19, 0x15, 0x13, 0x11, 0x11, 0x11}},
        {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
        {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
        {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}},
        {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
        {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
        {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}},
        {'f', {0x06, 0x09, 0x08, 0x1C, 0x08, 0x08, 0x08}},
        {'k', {0x10, 0x10, 0x12, 0x14, 0x18, 0x14, 0x12}},
        {'q', {0, 0, 0x0F, 0x11, 0x0F, 0x01, 0x01}},
        {'w', {0, 0, 0x11, 0x11, 0x15, 0x15, 0x0A}},
        {'x', {0, 0, 0x11, 0x0A, 0x04, 0x0A, 0x11}},
        {'z', {0, 0, 0x1F, 0x02, 0x04, 0x08, 0x1F}},
        {'=', {0, 0, 0x1F, 0, 0x1F, 0, 0}},
        {',', {0, 0, 0, 0, 0x0C, 0x04, 0x08}},
        {':', {0, 0x0C, 0x0C, 0, 0x0C, 0x0C, 0}},
        {'_', {0, 0, 0, 0, 0, 0, 0x1F}},
        {'<', {0x02, 0x04, 0x08, 0x10, 0x08, 0x04, 0x02}},
        {'>', {0x08, 0x04, 0x02, 0x01, 0x02, 0x04, 0x08}},
        {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
        {'a', {0, 0, 0x0E, 0x01, 0x0F, 0x11, 0x0F}},
        {'b', {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x1E}},
        {'c', {0, 0, 0x0E, 0x10, 0x10, 0x11, 0x0E}},
        {'d', {0x01, 0x01, 0x0D, 0x13, 0x11, 0x11, 0x0F}},
        {'e', {0, 0, 0x0E, 0x11, 0x1F, 0x10, 0x0E}},
        {'g', {0, 0x0F, 0x11, 0x11, 0x0F, 0x01, 0x0E}},
        {'h', {0x10, 0x10, 0x16, 0x19, 0x11, 0x11, 0x11}},
        {'i', {0x04, 0, 0x0C, 0x04, 0x04, 0x04, 0x0E}},
        {'j', {0x02, 0, 0x06, 0x02, 0x02, 0x12, 0x0C}},
        {'l', {0x0C, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}},
        {'m', {0, 0, 0x1A, 0x15, 0x15, 0x11, 0x11}},
        {'n', {0, 0, 0x16, 0x19, 0x11, 0x11, 0x11}},
        {'o', {0, 0, 0x0E, 0x11, 0x11, 0x11, 0x0E}},
        {'p', {0, 0, 0x1E, 0x11, 0x1E, 0x10, 0x10}},
        {'r', {0, 0, 0x16, 0x19, 0x10, 0x10, 0x10}},
        {'s', {0, 0, 0x0E, 0x10, 0x0E, 0x01, 0x1E}},
        {'t', {0x08, 0x08, 0x1C, 0x08, 0x08, 0x09, 0x06}},
        {'u', {0, 0, 0x11, 0x11, 0x11, 0x13, 0x0D}},
        {'v', {0, 0, 0x11, 0x11, 0x11, 0x0A, 0x04}},
        {'y', {0, 0, 0x11, 0x11, 0x0F, 0x01, 0x0E}}};
      return glyphs;
    }

    struct Image
    {
      Image(const int w, const int h)
        : width(w)
        , height(h)
        , rgb(3 * w * h, 255)
      {}

      void
      set(const int x, const int y, const std::array<std::uint8_t, 3> &c)
      {
        if (x < 0 || y < 0 || x >= width || y >= height)
          return;
        std::copy(c.begin(), c.end(), rgb.begin() + 3 * (y * width + x));
      }

      void
      line(double                             x0,
           double                             y0,
           double                             x1,
           double                             y1,
           const std::array<std::uint8_t, 3> &c,
           const int                          thickness = 1)
      {
        const int n =
          1 + static_cast<int>(std::max(std::abs(x1 - x0), std::abs(y1 - y0)));
        for (int k = 0; k <= n; ++k)
          {
            const double x = x0 + (x1 - x0) * k / n, y = y0 + (y1 - y0) * k / n;
            for (int dx = 0; dx < thickness; ++dx)
              for (int dy = 0; dy < thickness; ++dy)
                set(static_cast<int>(std::lround(x)) + dx - thickness / 2,
                    static_cast<int>(std::lround(y)) + dy - thickness / 2,
                    c);
          }
      }

      // Even-odd scanline fill of a polygon (pixel coordinates) at pixel
      // centers.
      void
      fill(const std::vector<std::array<double, 2>> &q,
           const std::array<std::uint8_t, 3>        &c)
      {
        double y0 = 1e300, y1 = -1e300;
        for (const auto &v : q)
          {
            y0 = std::min(y0, v[1]);
            y1 = std::max(y1, v[1]);
          }
        std::vector<double> xs;
        for (int y = static_cast<int>(std::floor(y0));
             y <= static_cast<int>(std::ceil(y1));
             ++y)
          {
            const double yc = y + 0.5;
            xs.clear();
            for (unsigned int i = 0; i < q.size(); ++i)
              {
                const auto &a = q[i], &b = q[(i + 1) % q.size()];
                if ((a[1] <= yc) != (b[1] <= yc))
                  xs.push_back(a[0] +
                               (yc - a[1]) / (b[1] - a[1]) * (b[0] - a[0]));
              }
            std::sort(xs.begin(), xs.end());
            for (unsigned int i = 0; i + 1 < xs.size(); i += 2)
              for (int x = static_cast<int>(std::ceil(xs[i] - 0.5));
                   x + 0.5 <= xs[i + 1];
                   ++x)
                set(x, y, c);
          }
      }

      // Text at (x, y) = top left, `scale` pixels per font pixel; vertical
      // text runs upwards.
      void
      text(const std::string                 &s,
           int                                x,
           int                                y,
           const int                          scale,
           const bool                         vertical = false,
           const std::array<std::uint8_t, 3> &color    = {0, 0, 0})
      {
        for (const char ch : s)
          {
            const auto it = font().find(ch);
            if (it != font().end())
              for (int r = 0; r < 7; ++r)
                for (int col = 0; col < 5; ++col)
                  if (it->second[r] & (0x10 >> col))
                    for (int a = 0; a < scale; ++a)
                      for (int b = 0; b < scale; ++b)
                        {
                          const int px = col * scale + a, py = r * scale + b;
                          if (vertical)
                            set(x + py, y - px, color);
                          else
                            set(x + px, y + py, color);
                        }
            (vertical ? y : x) += (vertical ? -6 : 6) * scale;
          }
      }

      static int
      text_width(const std::string &s, const int scale)
      {
        return 6 * scale * static_cast<int>(s.size());
      }

      void
      write_png(const std::string &file_name) const
      {
        std::vector<unsigned char> raw;
        raw.reserve((3 * width + 1) * height);
        for (int y = 0; y < height; ++y)
          {
            raw.push_back(0); // no filter
            raw.insert(raw.end(),
                       rgb.begin() + 3 * y * width,
                       rgb.begin() + 3 * (y + 1) * width);
          }
        uLongf                     size = compressBound(raw.size());
        std::vector<unsigned char> packed(size);
        AssertThrow(
          compress2(packed.data(), &size, raw.data(), raw.size(), 9) == Z_OK,
          dealii::ExcMessage("zlib failed to compress a plot"));
        packed.resize(size);

        std::ofstream out(file_name, std::ios::binary);
        AssertThrow(out,
                    dealii::ExcMessage("cannot write the plot '" + file_name +
                                       "'"));
        const unsigned char signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
        out.write(reinterpret_cast<const char *>(signature), 8);
        auto chunk = [&](const char                       *type,
                         const std::vector<unsigned char> &data) {
          auto be32 = [&](const std::uint32_t v) {
            const unsigned char b[4] = {static_cast<unsigned char>(v >> 24),
                                        static_cast<unsigned char>(v >> 16),
                                        static_cast<unsigned char>(v >> 8),
                                        static_cast<unsigned char>(v)};
            out.write(reinterpret_cast<const char *>(b), 4);
          };
          be32(data.size());
          out.write(type, 4);
          out.write(reinterpret_cast<const char *>(data.data()), data.size());
          uLong crc = crc32(0, reinterpret_cast<const Bytef *>(type), 4);
          crc       = crc32(crc, data.data(), data.size());
          be32(crc);
        };
        std::vector<unsigned char> header(13, 0);
        for (int k = 0; k < 4; ++k)
          {
            header[k]     = (width >> (24 - 8 * k)) & 255;
            header[4 + k] = (height >> (24 - 8 * k)) & 255;
          }
        header[8] = 8; // bit depth
        header[9] = 2; // RGB
        chunk("IHDR", header);
        chunk("IDAT", packed);
        chunk("IEND", {});
      }

      int                        width, height;
      std::vector<unsigned char> rgb;
    };

    // A "nice" tick spacing for a range shown with at most ~8 ticks.
    double
    nice_step(const double range)
    {
      const double raw  = range / 8;
      const double base = std::pow(10., std::floor(std::log10(raw)));
      for (const double m : {1., 2., 5., 10.})
        if (m * base >= raw)
          return m * base;
      return 10 * base;
    }

    std::string
    label(const double v)
    {
      std::ostringstream s;
      s << std::setprecision(3) << v;
      return s.str();
    }
  } // namespace



  void
  write_history_plot(const std::string         &file_name,
                     const std::vector<double> &values,
                     const std::string         &title,
                     const std::string         &x_label)
  {
    if (values.empty())
      return;
    const bool logarithmic =
      values.front() > 0 &&
      std::all_of(values.begin(), values.end(), [](double v) { return v > 0; });
    std::vector<double> y;
    for (const double v : values)
      y.push_back(logarithmic ? std::log10(v / values.front()) : v);

    double lo = *std::min_element(y.begin(), y.end());
    double hi = *std::max_element(y.begin(), y.end());
    double step;
    if (logarithmic)
      {
        lo   = std::floor(lo - 1e-9);
        hi   = std::max(std::ceil(hi - 1e-9), lo + 1);
        step = std::max(1., std::ceil((hi - lo) / 8));
      }
    else
      {
        if (hi - lo < 1e-12 * (std::abs(hi) + 1e-300))
          {
            lo -= 0.5 * std::abs(lo) + 1;
            hi += 0.5 * std::abs(hi) + 1;
          }
        step = nice_step(hi - lo);
        lo   = step * std::floor(lo / step);
        hi   = step * std::ceil(hi / step);
      }
    const double n_x = std::max<double>(1, values.size() - 1);

    Image     img(800, 500);
    const int left = 110, right = 770, top = 50, bottom = 430;
    auto      px = [&](double i) { return left + (right - left) * i / n_x; };
    auto      py = [&](double v) {
      return bottom - (bottom - top) * (v - lo) / (hi - lo);
    };
    const std::array<std::uint8_t, 3> grid{215, 215, 215}, axis{0, 0, 0},
      blue{31, 90, 180};

    for (double v = lo; v <= hi + 1e-9 * step; v += step)
      {
        img.line(left, py(v), right, py(v), grid);
        const std::string t =
          logarithmic ? "1e" + std::to_string(static_cast<int>(v)) : label(v);
        img.text(t, left - 10 - Image::text_width(t, 2), py(v) - 7, 2);
      }
    const double xs = std::max(1., nice_step(n_x));
    for (double i = 0; i <= n_x + 1e-9; i += xs)
      {
        img.line(px(i), top, px(i), bottom, grid);
        const std::string t = label(i);
        img.text(t, px(i) - Image::text_width(t, 2) / 2, bottom + 10, 2);
      }
    img.line(left, top, left, bottom, axis, 2);
    img.line(left, bottom, right, bottom, axis, 2);
    for (unsigned int i = 0; i + 1 < y.size(); ++i)
      img.line(px(i), py(y[i]), px(i + 1), py(y[i + 1]), blue, 3);
    for (unsigned int i = 0; i < y.size(); ++i)
      for (int d = -3; d <= 3; ++d)
        img.line(px(i) - 3, py(y[i]) + d, px(i) + 3, py(y[i]) + d, blue);

    img.text(title, (800 - Image::text_width(title, 3)) / 2, 12, 3);
    img.text(x_label,
             (left + right - Image::text_width(x_label, 2)) / 2,
             465,
             2);
    const std::string y_label = logarithmic ? "J/J0 (log)" : "J";
    img.text(
      y_label, 14, (top + bottom + Image::text_width(y_label, 2)) / 2, 2, true);
    img.write_png(file_name);
  }



  void
  write_xy_plot(const std::string             &file_name,
                const std::vector<PlotSeries> &series,
                const std::string             &title,
                const std::string             &x_label,
                const std::string             &y_label,
                const std::array<double, 2>   &x_range,
                const std::array<double, 2>   &y_range)
  {
    Image        img(800, 640);
    const int    left = 100, right = 770, top = 50, bottom = 570;
    const double x0 = x_range[0], x1 = x_range[1], y0 = y_range[0],
                 y1 = y_range[1];
    AssertThrow(x1 > x0 && y1 > y0,
                dealii::ExcMessage("empty plot range for '" + file_name + "'"));
    auto px = [&](double x) {
      return left + (right - left) * (x - x0) / (x1 - x0);
    };
    auto py = [&](double y) {
      return bottom - (bottom - top) * (y - y0) / (y1 - y0);
    };
    const std::array<std::uint8_t, 3> grid{215, 215, 215}, axis{0, 0, 0};
    const double xs = nice_step(x1 - x0), ys = nice_step(y1 - y0);
    for (double v = xs * std::ceil(x0 / xs - 1e-9); v <= x1 + 1e-9 * xs;
         v += xs)
      {
        img.line(px(v), top, px(v), bottom, grid);
        const std::string t = label(std::abs(v) < 1e-12 * xs ? 0. : v);
        img.text(t, px(v) - Image::text_width(t, 2) / 2, bottom + 10, 2);
      }
    for (double v = ys * std::ceil(y0 / ys - 1e-9); v <= y1 + 1e-9 * ys;
         v += ys)
      {
        img.line(left, py(v), right, py(v), grid);
        const std::string t = label(std::abs(v) < 1e-12 * ys ? 0. : v);
        img.text(t, left - 10 - Image::text_width(t, 2), py(v) - 7, 2);
      }
    img.line(left, top, left, bottom, axis, 2);
    img.line(left, bottom, right, bottom, axis, 2);
    auto inside = [&](double x, double y) {
      return x >= x0 && x <= x1 && y >= y0 && y <= y1;
    };
    for (const PlotSeries &s : series)
      {
        if (s.line)
          {
            for (unsigned int i = 0; i + 1 < s.points.size(); ++i)
              if (inside(s.points[i][0], s.points[i][1]) &&
                  inside(s.points[i + 1][0], s.points[i + 1][1]))
                img.line(px(s.points[i][0]),
                         py(s.points[i][1]),
                         px(s.points[i + 1][0]),
                         py(s.points[i + 1][1]),
                         s.color,
                         2);
          }
        else
          for (const auto &p : s.points)
            if (inside(p[0], p[1]))
              for (int d = -s.size; d <= s.size; ++d)
                img.line(px(p[0]) - s.size,
                         py(p[1]) + d,
                         px(p[0]) + s.size,
                         py(p[1]) + d,
                         s.color);
      }
    // Legend, top right.
    int row = top + 10;
    for (const PlotSeries &s : series)
      if (!s.label.empty())
        {
          const int x = right - 10 - Image::text_width(s.label, 2) - 30;
          for (int d = -3; d <= 3; ++d)
            img.line(x, row + 7 + d, x + 20, row + 7 + d, s.color);
          img.text(s.label, x + 28, row, 2);
          row += 22;
        }
    img.text(title, (800 - Image::text_width(title, 3)) / 2, 12, 3);
    img.text(x_label,
             (left + right - Image::text_width(x_label, 2)) / 2,
             605,
             2);
    img.text(
      y_label, 14, (top + bottom + Image::text_width(y_label, 2)) / 2, 2, true);
    img.write_png(file_name);
  }



  void
  write_polygon_field_png(
    const std::string                                     &file_name,
    const std::vector<std::vector<std::array<double, 2>>> &polygons,
    const std::vector<double>                             &values,
    const std::array<double, 2>                           &range,
    const std::string                                     &title,
    const int                                              width)
  {
    AssertThrow(polygons.size() == values.size() && !polygons.empty(),
                dealii::ExcMessage("polygon plot: one value per polygon"));
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (const auto &p : polygons)
      for (const auto &v : p)
        for (unsigned int d = 0; d < 2; ++d)
          {
            lo[d] = std::min(lo[d], v[d]);
            hi[d] = std::max(hi[d], v[d]);
          }
    const int    margin = 20, top = 50, bar = 120;
    const double extent = std::max(hi[0] - lo[0], 1e-300);
    const double scale  = (width - 2 * margin - bar) / extent;
    const int    height =
      top + margin + std::max(200, static_cast<int>((hi[1] - lo[1]) * scale));
    Image      img(width, height);
    const auto px = [&](const std::array<double, 2> &v) {
      return std::array<double, 2>{
        {margin + (v[0] - lo[0]) * scale, top + (hi[1] - v[1]) * scale}};
    };
    const auto color = [&](const double value) {
      const double t =
        std::clamp((value - range[0]) / std::max(range[1] - range[0], 1e-300),
                   0.,
                   1.);
      // blue -> cyan -> green -> yellow -> red
      const double                stops[5][3] = {{40, 60, 200},
                                                 {40, 190, 220},
                                                 {60, 180, 60},
                                                 {240, 210, 40},
                                                 {210, 40, 30}};
      const double                s           = 4 * t;
      const int                   k = std::min(3, static_cast<int>(s));
      std::array<std::uint8_t, 3> c;
      for (unsigned int i = 0; i < 3; ++i)
        c[i] = static_cast<std::uint8_t>(
          stops[k][i] + (s - k) * (stops[k + 1][i] - stops[k][i]));
      return c;
    };
    for (unsigned int k = 0; k < polygons.size(); ++k)
      {
        std::vector<std::array<double, 2>> q;
        for (const auto &v : polygons[k])
          q.push_back(px(v));
        img.fill(q, color(values[k]));
      }
    for (const auto &p : polygons)
      for (unsigned int i = 0; i < p.size(); ++i)
        {
          const auto a = px(p[i]), b = px(p[(i + 1) % p.size()]);
          img.line(a[0], a[1], b[0], b[1], {90, 90, 90});
        }
    // Color bar with its range.
    const int bx = width - bar + 30, by0 = top, by1 = height - margin;
    for (int y = by0; y <= by1; ++y)
      {
        const auto c =
          color(range[1] - (range[1] - range[0]) * (y - by0) / (by1 - by0));
        for (int x = bx; x < bx + 20; ++x)
          img.set(x, y, c);
      }
    const auto label = [](const double v) {
      std::ostringstream o;
      o << std::setprecision(3) << v;
      return o.str();
    };
    img.text(label(range[1]), bx + 24, by0, 2);
    img.text(label(range[0]), bx + 24, by1 - 14, 2);
    img.text(title, (width - Image::text_width(title, 2)) / 2, 15, 2);
    img.write_png(file_name);
  }



  void
  write_overlay_png(
    const std::string                                     &file_name,
    const std::vector<std::vector<std::array<double, 2>>> &filled,
    const std::vector<std::vector<std::array<double, 2>>> &outlined,
    const int                                              width)
  {
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (const auto *set : {&filled, &outlined})
      for (const auto &p : *set)
        for (const auto &v : p)
          for (unsigned int d = 0; d < 2; ++d)
            {
              lo[d] = std::min(lo[d], v[d]);
              hi[d] = std::max(hi[d], v[d]);
            }
    AssertThrow(hi[0] > lo[0],
                dealii::ExcMessage("overlay plot: nothing to draw"));
    const int    margin = 10;
    const double scale  = (width - 2 * margin) / (hi[0] - lo[0]);
    const int    height =
      2 * margin + static_cast<int>(std::ceil((hi[1] - lo[1]) * scale));
    Image      img(width, height);
    const auto px = [&](const std::array<double, 2> &v) {
      return std::array<double, 2>{
        {margin + (v[0] - lo[0]) * scale, margin + (hi[1] - v[1]) * scale}};
    };
    std::vector<std::array<double, 2>> q;
    for (const auto &p : filled)
      {
        q.clear();
        for (const auto &v : p)
          q.push_back(px(v));
        img.fill(q, {110, 110, 110});
      }
    for (const auto &p : outlined)
      for (unsigned int i = 0; i < p.size(); ++i)
        {
          const auto a = px(p[i]), b = px(p[(i + 1) % p.size()]);
          img.line(a[0], a[1], b[0], b[1], {210, 30, 30});
        }
    img.write_png(file_name);
  }



  void
  write_image_png(const std::string                &file_name,
                  const int                         width,
                  const int                         height,
                  const std::vector<unsigned char> &rgb)
  {
    AssertThrow(width > 0 && height > 0 &&
                  rgb.size() == 3 * static_cast<std::size_t>(width) * height,
                dealii::ExcMessage(
                  "write_image_png: " + std::to_string(rgb.size()) +
                  " bytes do not make a " + std::to_string(width) + " x " +
                  std::to_string(height) + " RGB image"));
    Image img(width, height);
    img.rgb = rgb;
    img.write_png(file_name);
  }


  void
  write_polygons_svg(
    const std::string                                     &file_name,
    const std::vector<std::vector<std::array<double, 2>>> &polygons,
    const double                                           stroke)
  {
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (const auto &polygon : polygons)
      for (const auto &v : polygon)
        for (unsigned int d = 0; d < 2; ++d)
          {
            lo[d] = std::min(lo[d], v[d]);
            hi[d] = std::max(hi[d], v[d]);
          }
    const double  pad = 2 * stroke;
    std::ofstream out(file_name);
    out << std::setprecision(9);
    // One unit is one millimetre (cutters read unitless sizes as pixels).
    const double w = hi[0] - lo[0] + 2 * pad, h = hi[1] - lo[1] + 2 * pad;
    out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w
        << "mm\" height=\"" << h << "mm\" viewBox=\"" << lo[0] - pad << " "
        << -hi[1] - pad << " " << w << " " << h
        << "\">\n<path fill=\"#282828\" "
        << "fill-rule=\"evenodd\" stroke=\"black\" stroke-width=\"" << stroke
        << "\" d=\"";
    for (const auto &polygon : polygons)
      for (unsigned int k = 0; k < polygon.size(); ++k)
        out << (k == 0 ? "M" : "L") << polygon[k][0] << " " << -polygon[k][1]
            << (k + 1 == polygon.size() ? "Z" : " ");
    out << "\"/>\n</svg>\n";
  }


  void
  write_level_set_png(const std::string                           &file_name,
                      const std::function<double(double, double)> &phi,
                      const std::array<double, 2>                 &lo,
                      const std::array<double, 2>                 &hi,
                      const int                                    width)
  {
    const int    margin = 10;
    const double scale  = (width - 2 * margin) / (hi[0] - lo[0]);
    const int    height =
      2 * margin + static_cast<int>(std::ceil((hi[1] - lo[1]) * scale));
    std::vector<unsigned char> rgb(3 * width * height, 255);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        if (phi(lo[0] + (x + 0.5 - margin) / scale,
                hi[1] - (y + 0.5 - margin) / scale) < 0)
          for (unsigned int k = 0; k < 3; ++k)
            rgb[3 * (y * width + x) + k] = 40;
    write_image_png(file_name, width, height, rgb);
  }
} // namespace forma
