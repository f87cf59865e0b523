#include <deal.II/base/exceptions.h>

#include <forma/base/plot.h>

#include "plot_axes.h"
#include "plot_canvas.h"
#include "plot_data.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace forma
{
  namespace
  {
    using internal::Anchor;
    using internal::Canvas;
    using internal::Color;
    using internal::number;
    using internal::Point;
    using Polygons = std::vector<std::vector<Point>>;

    std::string
    hex(const Color &c)
    {
      char s[8];
      std::snprintf(s, sizeof(s), "#%02x%02x%02x", c[0], c[1], c[2]);
      return s;
    }

    // The bounding box {lo, hi} of polygon sets.
    std::array<Point, 2>
    bounding_box(const std::vector<const Polygons *> &sets)
    {
      std::array<Point, 2> box{{{{1e300, 1e300}}, {{-1e300, -1e300}}}};
      for (const Polygons *set : sets)
        for (const auto &p : *set)
          for (const Point &v : p)
            for (unsigned int d = 0; d < 2; ++d)
              {
                box[0][d] = std::min(box[0][d], v[d]);
                box[1][d] = std::max(box[1][d], v[d]);
              }
      return box;
    }

    // Legend entries beside the plot area, from its top right corner.
    void
    draw_legend(Canvas                        &canvas,
                const std::vector<PlotSeries> &series,
                const Point                   &corner)
    {
      double y = corner[1] + 12;
      for (const PlotSeries &s : series)
        if (!s.label.empty())
          {
            canvas.set_color(s.color);
            if (s.line)
              canvas.line({{corner[0], y}}, {{corner[0] + 24, y}}, 2.5);
            else
              canvas.disc({{corner[0] + 12, y}}, s.size + 1.5);
            canvas.set_color({{0, 0, 0}});
            canvas.text(s.label, {{corner[0] + 32, y}}, 13);
            y += 24;
          }
    }

    // Series and legend: lines clipped to the frame, points drawn whole
    // where they lie in it (on its edges too).
    void
    draw_series(Canvas                        &canvas,
                const internal::Frame         &frame,
                const std::vector<PlotSeries> &series)
    {
      const auto inside = [&](const double v, const internal::Axis &a) {
        const double u = a.unit(v);
        return u > -1e-9 && u < 1 + 1e-9;
      };
      // Off a logarithmic axis (v <= 0) or not finite: a gap in a line.
      const auto drawable = [&](const std::array<double, 2> &p) {
        return std::isfinite(p[0]) && std::isfinite(p[1]) &&
               (!frame.x.logarithmic || p[0] > 0) &&
               (!frame.y.logarithmic || p[1] > 0);
      };
      for (const PlotSeries &s : series)
        {
          canvas.set_color(s.color);
          if (s.line)
            {
              canvas.clip({{frame.left, frame.top}},
                          {{frame.right, frame.bottom}});
              std::vector<Point> run;
              for (unsigned int i = 0; i <= s.points.size(); ++i)
                if (i < s.points.size() && drawable(s.points[i]))
                  run.push_back(frame.at(s.points[i]));
                else
                  {
                    canvas.stroke(run, 2.5);
                    run.clear();
                  }
              canvas.unclip();
            }
          else
            for (const auto &p : s.points)
              if (drawable(p) && inside(p[0], frame.x) && inside(p[1], frame.y))
                canvas.disc(frame.at(p), s.size + 0.5);
        }
      draw_legend(canvas, series, {{frame.right + 20, frame.top}});
    }

    // Whether every x (range and points) is a whole number: iterations,
    // beam counts; the x ticks then are whole numbers too.
    bool
    whole_x(const std::vector<PlotSeries> &series,
            const std::array<double, 2>   &range)
    {
      const auto whole = [](const double x) { return x == std::round(x); };
      bool       all   = whole(range[0]) && whole(range[1]);
      for (const PlotSeries &s : series)
        for (const auto &p : s.points)
          all = all && whole(p[0]);
      return all;
    }

    double
    legend_width(const std::vector<PlotSeries> &series)
    {
      Canvas measure("measure.png", 1, 1); // never saved
      double w = 0;
      for (const PlotSeries &s : series)
        if (!s.label.empty())
          w = std::max(w, measure.text_width(s.label, 13) + 60);
      return w;
    }

    /// A range of one value (a study of one point, data all equal) gets
    /// room around it; any other range is left as it is.
    std::array<double, 2>
    widened(const std::array<double, 2> &range, const bool logarithmic)
    {
      const double v = range[0];
      if (!(range[1] == v) || !std::isfinite(v) || (logarithmic && !(v > 0)))
        return range;
      if (logarithmic)
        return {{v / 1.1, v * 1.1}};
      const double pad = std::max(0.05 * std::abs(v), 0.05);
      return {{v - pad, v + pad}};
    }

    void
    check_range(const std::string           &file_name,
                const std::array<double, 2> &range,
                const bool                   logarithmic)
    {
      AssertThrow(std::isfinite(range[0]) && std::isfinite(range[1]) &&
                    range[1] > range[0] && (!logarithmic || range[0] > 0),
                  dealii::ExcMessage(
                    "the plot '" + file_name + "' has an empty range [" +
                    internal::tick_label(range[0]) + ", " +
                    internal::tick_label(range[1]) + "]" +
                    (logarithmic ? " on a logarithmic axis" : "")));
    }
  } // namespace



  namespace
  {
    // write_xy_plot() with `extra` lines for the data file's header.
    void
    xy_plot(const std::string                                      &file_name,
            const std::vector<PlotSeries>                          &series,
            const std::string                                      &title,
            const std::string                                      &x_label,
            const std::string                                      &y_label,
            const std::array<double, 2>                            &x_given,
            const std::array<double, 2>                            &y_given,
            const std::array<bool, 2>                              &logarithmic,
            const std::vector<std::pair<std::string, std::string>> &extra)
    {
      const std::array<double, 2> x_range = widened(x_given, logarithmic[0]);
      const std::array<double, 2> y_range = widened(y_given, logarithmic[1]);
      check_range(file_name, x_range, logarithmic[0]);
      check_range(file_name, y_range, logarithmic[1]);
      const double          width = 820 + legend_width(series), height = 640;
      const internal::Frame frame{
        100,
        790,
        50,
        560,
        {x_range[0], x_range[1], logarithmic[0], whole_x(series, x_range)},
        {y_range[0], y_range[1], logarithmic[1], false}};
      Canvas canvas(file_name, width, height);
      internal::draw_frame(canvas, frame, width, title, x_label, y_label);
      draw_series(canvas, frame, series);
      canvas.save();

      std::vector<std::pair<std::string, std::string>> meta = {
        {"forma plot", "xy"},
        {"title", title},
        {"x label", x_label},
        {"y label", y_label},
        {"x range", number(x_range[0]) + " " + number(x_range[1])},
        {"y range", number(y_range[0]) + " " + number(y_range[1])},
        {"logarithmic",
         std::string(logarithmic[0] ? "x" : "") + (logarithmic[1] ? "y" : "")}};
      meta.insert(meta.end(), extra.begin(), extra.end());
      internal::write_plot_data(file_name,
                                meta,
                                "series,label,style,color,size,x,y",
                                [&](std::ostream &out) {
                                  for (unsigned int i = 0; i < series.size();
                                       ++i)
                                    for (const auto &p : series[i].points)
                                      out
                                        << i << ','
                                        << internal::csv_quote(series[i].label)
                                        << ','
                                        << (series[i].line ? "line" : "points")
                                        << ',' << hex(series[i].color) << ','
                                        << series[i].size << ',' << number(p[0])
                                        << ',' << number(p[1]) << '\n';
                                });
    }
  } // namespace



  void
  write_xy_plot(const std::string             &file_name,
                const std::vector<PlotSeries> &series,
                const std::string             &title,
                const std::string             &x_label,
                const std::string             &y_label,
                const std::array<double, 2>   &x_range,
                const std::array<double, 2>   &y_range,
                const std::array<bool, 2>     &logarithmic)
  {
    xy_plot(file_name,
            series,
            title,
            x_label,
            y_label,
            x_range,
            y_range,
            logarithmic,
            {});
  }



  void
  write_history_plot(const std::string               &file_name,
                     const std::vector<double>       &values,
                     const std::string               &title,
                     const std::string               &x_label,
                     const std::vector<unsigned int> &marks,
                     const std::string               &mark_label)
  {
    if (values.empty())
      return;
    const bool logarithmic =
      std::all_of(values.begin(), values.end(), [](double v) {
        return v > 0 && std::isfinite(v);
      });
    std::vector<Point> points;
    for (unsigned int i = 0; i < values.size(); ++i)
      points.push_back(
        {{double(i), logarithmic ? values[i] / values[0] : values[i]}});
    double lo = 1e300, hi = -1e300;
    for (const Point &p : points)
      if (std::isfinite(p[1]))
        lo = std::min(lo, p[1]), hi = std::max(hi, p[1]);
    if (!(hi >= lo))
      lo = 0, hi = 1;
    if (logarithmic) // whole decades
      {
        lo = std::pow(10., std::floor(std::log10(lo) + 1e-9));
        hi = std::max(std::pow(10., std::ceil(std::log10(hi) - 1e-9)), 10 * lo);
      }
    else
      {
        const double span = hi - lo;
        const double pad  = span > 1e-12 * (std::abs(hi) + 1e-300) ?
                              0.05 * span :
                              0.5 * std::abs(hi) + 1;
        lo -= pad;
        hi += pad;
      }
    PlotSeries line, dots;
    line.points = dots.points = points;
    line.line                 = true;
    dots.size                 = 3;
    std::vector<PlotSeries> series{line};
    if (values.size() <= 200)
      series.push_back(dots);
    PlotSeries marked;
    for (const unsigned int i : marks)
      if (i < points.size())
        marked.points.push_back(points[i]);
    if (!marked.points.empty())
      {
        marked.color = {{230, 120, 20}};
        marked.size  = 5;
        marked.label = mark_label;
        series.push_back(marked);
      }
    // J0 in the data file: y holds J / J0 on a logarithmic axis.
    xy_plot(file_name,
            series,
            title,
            x_label,
            logarithmic ? "J / J₀" : "J",
            {{0., std::max(1., values.size() - 1.)}},
            {{lo, hi}},
            {{false, logarithmic}},
            {{"J0", number(values[0])}});
  }



  void
  write_polygon_field(const std::string           &file_name,
                      const Polygons              &polygons,
                      const std::vector<double>   &values,
                      const std::array<double, 2> &range,
                      const std::string           &title,
                      const int                    width)
  {
    AssertThrow(polygons.size() == values.size() && !polygons.empty(),
                dealii::ExcMessage("the plot '" + file_name +
                                   "' needs one value per polygon"));
    const auto   box    = bounding_box({&polygons});
    const double margin = 20, top = 50, bar = 130;
    const double scale =
      (width - 2 * margin - bar) / std::max(box[1][0] - box[0][0], 1e-300);
    const double height =
      top + margin + std::max(200., (box[1][1] - box[0][1]) * scale);
    const auto at = [&](const Point &v) {
      return Point{{margin + (v[0] - box[0][0]) * scale,
                    top + (box[1][1] - v[1]) * scale}};
    };
    const auto unit = [&](const double v) {
      return (v - range[0]) / std::max(range[1] - range[0], 1e-300);
    };
    Canvas canvas(file_name, width, height);
    for (unsigned int k = 0; k < polygons.size(); ++k)
      {
        std::vector<Point> q;
        for (const Point &v : polygons[k])
          q.push_back(at(v));
        canvas.set_color(internal::color_scale(unit(values[k])));
        canvas.fill({q});
        canvas.set_color({{90, 90, 90}});
        canvas.stroke(q, 0.6, true);
      }
    // Color bar with five labelled values.
    const double bx = width - bar + 20, by0 = top, by1 = height - margin;
    const int    n = 128;
    for (int i = 0; i < n; ++i)
      {
        canvas.set_color(internal::color_scale(1 - (i + 0.5) / n));
        canvas.rectangle({{bx, by0 + (by1 - by0) * i / n}},
                         {{bx + 20, by0 + (by1 - by0) * (i + 1) / n + 0.5}});
      }
    canvas.set_color({{0, 0, 0}});
    for (int i = 0; i <= 4; ++i)
      canvas.text(internal::tick_label(range[1] -
                                       (range[1] - range[0]) * i / 4),
                  {{bx + 26, by0 + (by1 - by0) * i / 4}},
                  12);
    canvas.text(title, {{width / 2., 24}}, 16, Anchor::center);
    canvas.save();

    internal::write_plot_data(
      file_name,
      {{"forma plot", "polygon field"},
       {"title", title},
       {"range", number(range[0]) + " " + number(range[1])}},
      "polygon,value,x,y",
      [&](std::ostream &out) {
        for (unsigned int k = 0; k < polygons.size(); ++k)
          for (const Point &v : polygons[k])
            out << k << ',' << number(values[k]) << ',' << number(v[0]) << ','
                << number(v[1]) << '\n';
      });
  }



  void
  write_overlay(const std::string &file_name,
                const Polygons    &filled,
                const Polygons    &outlined,
                const int          width)
  {
    const auto box = bounding_box({&filled, &outlined});
    AssertThrow(box[1][0] > box[0][0],
                dealii::ExcMessage("the overlay plot '" + file_name +
                                   "' has nothing to draw"));
    const double margin = 10;
    const double scale  = (width - 2 * margin) / (box[1][0] - box[0][0]);
    const double height =
      2 * margin + std::ceil((box[1][1] - box[0][1]) * scale);
    const auto at = [&](const Point &v) {
      return Point{{margin + (v[0] - box[0][0]) * scale,
                    margin + (box[1][1] - v[1]) * scale}};
    };
    Canvas canvas(file_name, width, height);
    canvas.set_color({{110, 110, 110}});
    for (const auto &p : filled) // one by one: overlaps stay filled
      {
        std::vector<Point> q;
        for (const Point &v : p)
          q.push_back(at(v));
        canvas.fill({q});
        canvas.stroke(q, 0.6, true); // no light seams between cells
      }
    canvas.set_color({{210, 30, 30}});
    for (const auto &p : outlined)
      {
        std::vector<Point> q;
        for (const Point &v : p)
          q.push_back(at(v));
        canvas.stroke(q, 1, true);
      }
    canvas.save();

    internal::write_plot_data(file_name,
                              {{"forma plot", "overlay"}},
                              "set,polygon,x,y",
                              [&](std::ostream &out) {
                                for (const auto &[name, set] :
                                     {std::make_pair("filled", &filled),
                                      std::make_pair("outlined", &outlined)})
                                  for (unsigned int k = 0; k < set->size(); ++k)
                                    for (const Point &v : (*set)[k])
                                      out << name << ',' << k << ','
                                          << number(v[0]) << ',' << number(v[1])
                                          << '\n';
                              });
  }



  void
  write_image(const std::string                &file_name,
              const int                         width,
              const int                         height,
              const std::vector<unsigned char> &rgb)
  {
    AssertThrow(width > 0 && height > 0 &&
                  rgb.size() == 3 * static_cast<std::size_t>(width) * height,
                dealii::ExcMessage("the image '" + file_name +
                                   "': " + std::to_string(rgb.size()) +
                                   " bytes do not make a " +
                                   std::to_string(width) + " x " +
                                   std::to_string(height) + " RGB image"));
    Canvas canvas(file_name, width, height);
    canvas.image(width, height, rgb);
    canvas.save();
  }



  void
  write_level_set(const std::string                           &file_name,
                  const std::function<double(double, double)> &phi,
                  const std::array<double, 2>                 &lo,
                  const std::array<double, 2>                 &hi,
                  const int                                    width)
  {
    AssertThrow(hi[0] > lo[0] && hi[1] > lo[1] && width > 20,
                dealii::ExcMessage("the level set picture '" + file_name +
                                   "' has an empty box"));
    const int    margin = 10;
    const double scale  = (width - 2 * margin) / (hi[0] - lo[0]);
    const int    height =
      2 * margin + static_cast<int>(std::ceil((hi[1] - lo[1]) * scale));
    std::vector<unsigned char> rgb(3 * std::size_t(width) * height, 255);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x)
        if (phi(lo[0] + (x + 0.5 - margin) / scale,
                hi[1] - (y + 0.5 - margin) / scale) < 0)
          for (unsigned int k = 0; k < 3; ++k)
            rgb[3 * (std::size_t(y) * width + x) + k] = 40;
    write_image(file_name, width, height, rgb);
  }


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
                     const unsigned int             per_row)
  {
    const std::size_t n = std::size_t(n_rows) * n_columns;
    AssertThrow(!panels.empty() && n > 0 && per_row > 0,
                dealii::ExcMessage("the plot '" + file_name +
                                   "' has no panels or an empty grid"));
    for (const FieldPanel &p : panels)
      AssertThrow(p.values.size() == n &&
                    (p.defined.empty() || p.defined.size() == n),
                  dealii::ExcMessage("the panel '" + p.title + "' of '" +
                                     file_name + "' does not match its grid"));
    check_range(file_name, x_range, false);
    check_range(file_name, y_range, false);
    const double       side = 160, gap = 30, left = 90, top = 50;
    const unsigned int columns = std::min<unsigned int>(per_row, panels.size());
    const unsigned int rows    = (panels.size() + per_row - 1) / per_row;
    const double       width   = left + columns * (side + gap) + 20;
    const double       height  = top + rows * (side + 2 * gap) + 12;
    Canvas             canvas(file_name, width, height);
    const auto         defined = [&](const FieldPanel &p, const std::size_t i) {
      return (p.defined.empty() || p.defined[i]) && std::isfinite(p.values[i]);
    };
    for (unsigned int k = 0; k < panels.size(); ++k)
      {
        const FieldPanel &p  = panels[k];
        double            lo = 1e300, hi = -1e300;
        for (std::size_t i = 0; i < n; ++i)
          if (defined(p, i))
            lo = std::min(lo, p.values[i]), hi = std::max(hi, p.values[i]);
        std::vector<unsigned char> rgb(3 * n);
        for (std::size_t i = 0; i < n; ++i)
          {
            const Color c =
              defined(p, i) ?
                internal::color_scale(hi > lo ? (p.values[i] - lo) / (hi - lo) :
                                                0.5) :
                Color{{200, 200, 200}};
            std::copy(c.begin(), c.end(), rgb.begin() + 3 * i);
          }
        const Point corner{{left + (k % per_row) * (side + gap),
                            top + (k / per_row) * (side + 2 * gap)}};
        canvas.image(n_columns, n_rows, rgb, corner, {{side, side}});
        canvas.set_color({{0, 0, 0}});
        canvas.stroke({corner,
                       {{corner[0] + side, corner[1]}},
                       {{corner[0] + side, corner[1] + side}},
                       {{corner[0], corner[1] + side}}},
                      1,
                      true);
        canvas.text(p.title,
                    {{corner[0] + side / 2, corner[1] - 10}},
                    14,
                    Anchor::center);
        canvas.text(hi >= lo ? internal::tick_label(lo) + " – " +
                                 internal::tick_label(hi) :
                               "no values",
                    {{corner[0] + side / 2, corner[1] + side + 12}},
                    11,
                    Anchor::center);
        if (k % per_row == 0) // the y range at the left
          {
            canvas.text(internal::tick_label(y_range[1]),
                        {{corner[0] - 6, corner[1] + 6}},
                        11,
                        Anchor::right);
            canvas.text(internal::tick_label(y_range[0]),
                        {{corner[0] - 6, corner[1] + side - 6}},
                        11,
                        Anchor::right);
          }
        if (k + per_row >= panels.size()) // the x range below the last row
          {
            canvas.text(internal::tick_label(x_range[0]),
                        {{corner[0], corner[1] + side + 26}},
                        11,
                        Anchor::left);
            canvas.text(internal::tick_label(x_range[1]),
                        {{corner[0] + side, corner[1] + side + 26}},
                        11,
                        Anchor::right);
          }
      }
    canvas.text(title, {{width / 2, 20}}, 16, Anchor::center);
    canvas.text(x_label, {{width / 2, height - 14}}, 14, Anchor::center);
    canvas.text(y_label, {{20, height / 2}}, 14, Anchor::center, true);
    canvas.save();

    // Each panel's title in the header: a panel without values has no rows.
    std::vector<std::pair<std::string, std::string>> meta = {
      {"forma plot", "field panels"},
      {"title", title},
      {"x label", x_label},
      {"y label", y_label},
      {"x range", number(x_range[0]) + " " + number(x_range[1])},
      {"y range", number(y_range[0]) + " " + number(y_range[1])},
      {"grid", std::to_string(n_rows) + " " + std::to_string(n_columns)},
      {"per row", std::to_string(per_row)},
      {"panels", std::to_string(panels.size())}};
    for (unsigned int k = 0; k < panels.size(); ++k)
      meta.emplace_back("panel " + std::to_string(k), panels[k].title);
    internal::write_plot_data(
      file_name, meta, "panel,title,row,column,value", [&](std::ostream &out) {
        for (unsigned int k = 0; k < panels.size(); ++k)
          for (std::size_t i = 0; i < n; ++i)
            if (defined(panels[k], i))
              out << k << ',' << internal::csv_quote(panels[k].title) << ','
                  << i / n_columns << ',' << i % n_columns << ','
                  << number(panels[k].values[i]) << '\n';
      });
  }
} // namespace forma
