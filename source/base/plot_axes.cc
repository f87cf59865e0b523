#include "plot_axes.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace forma
{
  namespace internal
  {
    namespace
    {
      // A "nice" tick spacing (1, 2 or 5 times a power of ten) for a range
      // shown with at most about 8 ticks.
      double
      nice_step(const double range)
      {
        const double raw  = range / 8;
        const double base = std::pow(10., std::floor(std::log10(raw)));
        for (const double m : {1., 2., 5., 10.})
          if (m * base >= raw * (1 - 1e-12))
            return m * base;
        return 10 * base;
      }

      bool
      is_decade(const double v)
      {
        const double k = std::log10(v);
        return std::abs(k - std::round(k)) < 1e-9;
      }

      const Color grid_color{{225, 225, 225}}, minor_color{{240, 240, 240}},
        black{{0, 0, 0}};
    } // namespace



    double
    Axis::unit(const double v) const
    {
      if (logarithmic)
        return (std::log10(v) - std::log10(lo)) /
               (std::log10(hi) - std::log10(lo));
      return (v - lo) / (hi - lo);
    }



    std::vector<double>
    Axis::ticks() const
    {
      std::vector<double> t;
      if (logarithmic)
        {
          const int k0    = static_cast<int>(std::ceil(std::log10(lo) - 1e-9));
          const int k1    = static_cast<int>(std::floor(std::log10(hi) + 1e-9));
          const int every = std::max(1, (k1 - k0 + 7) / 8);
          for (int k = k0; k <= k1; k += every)
            t.push_back(std::pow(10., k));
          if (t.size() >= 2)
            return t;
          // Within a decade or two: 1..9 (or 1, 2, 5) times the powers of
          // ten, or else (a narrow range) the linear ticks.
          t = minor_ticks();
          if (t.size() > 10)
            t.erase(std::remove_if(
                      t.begin(),
                      t.end(),
                      [](const double v) {
                        const double j = std::round(
                          v / std::pow(10., std::floor(std::log10(v) + 1e-9)));
                        return j != 1 && j != 2 && j != 5;
                      }),
                    t.end());
          if (t.size() >= 2)
            return t;
        }
      const double step = whole ? std::max(1., std::round(nice_step(hi - lo))) :
                                  nice_step(hi - lo);
      for (double v = step * std::ceil(lo / step - 1e-9); v <= hi + 1e-9 * step;
           v += step)
        if (!logarithmic || v > 0)
          t.push_back(std::abs(v) < 1e-9 * step ? 0. : v);
      return t;
    }



    std::vector<double>
    Axis::minor_ticks() const
    {
      std::vector<double> t;
      if (!logarithmic || std::log10(hi / lo) > 6)
        return t;
      for (int k = static_cast<int>(std::floor(std::log10(lo)));
           k <= static_cast<int>(std::ceil(std::log10(hi)));
           ++k)
        for (int j = 1; j <= 9; ++j)
          {
            const double v = j * std::pow(10., k);
            if (v >= lo * (1 - 1e-12) && v <= hi * (1 + 1e-12))
              t.push_back(v);
          }
      return t;
    }



    Point
    Frame::at(const double xv, const double yv) const
    {
      return {{left + (right - left) * x.unit(xv),
               bottom - (bottom - top) * y.unit(yv)}};
    }



    std::string
    tick_label(const double v)
    {
      std::ostringstream s;
      s << std::setprecision(3) << v;
      return s.str();
    }



    namespace
    {
      void
      draw_tick_label(Canvas      &canvas,
                      const Axis  &axis,
                      const double v,
                      const Point &at,
                      const Anchor anchor)
      {
        const double size = 13;
        if (axis.logarithmic && is_decade(v))
          {
            const int    k = static_cast<int>(std::round(std::log10(v)));
            const double shift =
              anchor == Anchor::right ?
                0. :
                canvas.text_width("10" + std::to_string(k), size) / 2;
            canvas.power_of_ten(k, {{at[0] + shift, at[1]}}, size);
          }
        else
          canvas.text(tick_label(v), at, size, anchor);
      }
    } // namespace



    void
    draw_frame(Canvas            &canvas,
               const Frame       &frame,
               const double       width,
               const std::string &title,
               const std::string &x_label,
               const std::string &y_label)
    {
      const Frame &f = frame;
      canvas.set_color(minor_color);
      for (const double v : f.x.minor_ticks())
        canvas.line(f.at(v, f.y.lo), f.at(v, f.y.hi), 1);
      for (const double v : f.y.minor_ticks())
        canvas.line(f.at(f.x.lo, v), f.at(f.x.hi, v), 1);
      for (const double v : f.x.ticks())
        {
          canvas.set_color(grid_color);
          canvas.line(f.at(v, f.y.lo), f.at(v, f.y.hi), 1);
          canvas.set_color(black);
          const Point p = f.at(v, f.y.lo);
          draw_tick_label(canvas, f.x, v, {{p[0], p[1] + 18}}, Anchor::center);
        }
      for (const double v : f.y.ticks())
        {
          canvas.set_color(grid_color);
          canvas.line(f.at(f.x.lo, v), f.at(f.x.hi, v), 1);
          canvas.set_color(black);
          const Point p = f.at(f.x.lo, v);
          draw_tick_label(canvas, f.y, v, {{p[0] - 8, p[1]}}, Anchor::right);
        }
      canvas.set_color(black);
      canvas.stroke({{{f.left, f.top}},
                     {{f.left, f.bottom}},
                     {{f.right, f.bottom}},
                     {{f.right, f.top}}},
                    1.5,
                    true);
      canvas.text(title, {{width / 2, 24}}, 18, Anchor::center);
      canvas.text(x_label,
                  {{(f.left + f.right) / 2, f.bottom + 46}},
                  15,
                  Anchor::center);
      canvas.text(
        y_label, {{22, (f.top + f.bottom) / 2}}, 15, Anchor::center, true);
    }
  } // namespace internal
} // namespace forma
