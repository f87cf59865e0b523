// The plots (Cairo): PNG, SVG and PDF from one call; pixels where the data
// says (a y-up field, an image read back); the CSV beside each plot holds
// exactly the plotted numbers and redraws with contrib/plot/redraw.py;
// fabrication outlines as DXF; bad input refused without a file left.

#include <forma/base/outline.h>
#include <forma/base/plot.h>

#include "../tests.h"
#include <cairo/cairo.h>

#include <cstdint>
#include <filesystem>
#include <limits>

using namespace forma;
using dealii::deallog;

// The RGB of pixel (x, y) of a PNG, read back with Cairo.
std::array<int, 3>
pixel(const std::string &png, const int x, const int y)
{
  cairo_surface_t   *s = cairo_image_surface_create_from_png(png.c_str());
  std::array<int, 3> c{{-1, -1, -1}};
  if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS)
    {
      const auto *row =
        cairo_image_surface_get_data(s) + y * cairo_image_surface_get_stride(s);
      const std::uint32_t v = reinterpret_cast<const std::uint32_t *>(row)[x];
      c = {{int(v >> 16 & 255), int(v >> 8 & 255), int(v & 255)}};
    }
  cairo_surface_destroy(s);
  return c;
}

std::array<int, 2>
png_size(const std::string &png)
{
  cairo_surface_t         *s = cairo_image_surface_create_from_png(png.c_str());
  const std::array<int, 2> size{
    {cairo_image_surface_get_width(s), cairo_image_surface_get_height(s)}};
  cairo_surface_destroy(s);
  return size;
}

// The data rows of a plot's CSV (after its comments and header).
std::vector<std::string>
rows(const std::string &csv)
{
  std::istringstream       in(read_file(csv));
  std::vector<std::string> r;
  bool                     header = true;
  for (std::string line; std::getline(in, line);)
    if (line.rfind("# ", 0) == 0)
      continue;
    else if (header)
      header = false;
    else
      r.push_back(line);
  return r;
}

bool
starts_with(const std::string &file, const std::string &prefix)
{
  return read_file(file).rfind(prefix, 0) == 0;
}

void
redraw(const std::string &csv)
{
  const std::string command = "/usr/bin/python3 " FORMA_SOURCE_DIR
                              "/contrib/plot/redraw.py " +
                              csv + " " + csv + ".png > redraw.log 2>&1";
  const int status = std::system(command.c_str());
  check("redraw.py redraws " + csv,
        WEXITSTATUS(status) == 0 && starts_with(csv + ".png", "\x89PNG"));
}

int
main()
{
  initlog();

  // A history: log axis of J/J0, the values and J/J0 in the CSV.
  const std::vector<double> values = {2., 0.2, 0.02, 0.004};
  write_history_plot("history.png", values, "objective history", "iteration");
  check("history: a PNG of 820 x 640 pixels",
        png_size("history.png") == (std::array<int, 2>{{820, 640}}));
  const auto history = rows("history.plot.csv");
  deallog << "history.plot.csv: " << history.size() << " rows; first "
          << history.front() << std::endl;
  check("history.plot.csv says log y and J0 = 2",
        read_file("history.plot.csv").find("# logarithmic: y\n# J0: 2\n") !=
          std::string::npos);

  // An x-y plot in three formats; Greek labels; a legend beside the axes.
  PlotSeries bound, samples;
  bound.points   = {{{-1, 0}}, {{0, 0.5}}, {{1, 1}}};
  bound.line     = true;
  bound.color    = {{200, 60, 40}};
  bound.label    = "Hashin–Shtrikman, \"right\" bound";
  samples.points = {{{0.1, 0.3}}, {{0.25, 0.125}}};
  samples.label  = "samples, ν ≤ 0.3";
  for (const std::string extension : {".png", ".svg", ".pdf"})
    write_xy_plot("coverage" + extension,
                  {bound, samples},
                  "Coverage Δ_R",
                  "Poisson's ratio ν",
                  "E / E_b",
                  {{-1, 1}},
                  {{0.01, 1}},
                  {{false, true}});
  check("PNG, SVG and PDF written",
        starts_with("coverage.png", "\x89PNG") &&
          read_file("coverage.svg").find("<svg") != std::string::npos &&
          starts_with("coverage.pdf", "%PDF"));
  check("the legend widens the canvas", png_size("coverage.png")[0] > 820);
  for (const std::string &r : rows("coverage.plot.csv"))
    deallog << "  coverage.plot.csv: " << r << std::endl;
  // A range of one value (a study of one point) gets room around it.
  write_xy_plot("single.png",
                {bound},
                "one value",
                "x",
                "y",
                {{10, 10}},
                {{0.5, 0.5}},
                {{false, true}});
  check("a range of one value is widened",
        read_file("single.plot.csv").find("# x range: 9.5 10.5") !=
            std::string::npos &&
          starts_with("single.png", "\x89PNG"));

  // A field on two unit squares, y up: the low value at the bottom.
  const std::vector<std::vector<std::array<double, 2>>> squares = {
    {{{0, 0}}, {{1, 0}}, {{1, 1}}, {{0, 1}}},
    {{{0, 1}}, {{1, 1}}, {{1, 2}}, {{0, 2}}}};
  write_polygon_field("field.png", squares, {0., 1.}, {{0, 1}}, "E / E_b", 330);
  // width 330: margin 20 + 160 px per unit + color bar 130; top 50.
  const auto low  = pixel("field.png", 110, 50 + 270),
             high = pixel("field.png", 110, 50 + 90);
  deallog << "field: bottom square " << low[0] << " " << low[1] << " " << low[2]
          << ", top square " << high[0] << " " << high[1] << " " << high[2]
          << std::endl;
  deallog << "field.plot.csv: " << rows("field.plot.csv").size() << " rows"
          << std::endl;

  // No value (NaN): gray.
  write_polygon_field("nan.png",
                      squares,
                      {std::numeric_limits<double>::quiet_NaN(), 1.},
                      {{0, 1}},
                      "NaN",
                      330);
  const auto none = pixel("nan.png", 110, 50 + 270);
  deallog << "field: no value " << none[0] << " " << none[1] << " " << none[2]
          << std::endl;
  // A log axis inside two decades: labelled at 1, 2 and 5 times 10^k.
  write_xy_plot("narrow.png",
                {samples},
                "narrow",
                "x",
                "y",
                {{0, 1}},
                {{0.02, 0.5}},
                {{false, true}});
  check("a log axis inside two decades drawn",
        starts_with("narrow.png", "\x89PNG"));

  write_overlay("overlay.svg", squares, {squares[0]}, 400);
  check("overlay: an SVG and its CSV",
        read_file("overlay.svg").find("<svg") != std::string::npos &&
          rows("overlay.plot.csv").size() == 12);

  // Panels: two fields on a 2 x 3 grid, one point undefined (gray).
  FieldPanel f1{"p_1", {0, 1, 2, 3, 4, 5}, {}},
    f2{"p_2", {5, 4, 3, 2, 1, 0}, {true, true, true, true, true, false}};
  write_field_panels("panels.png",
                     {f1, f2},
                     2,
                     3,
                     {{0, 0.4}},
                     {{0.02, 0.1}},
                     "α = 90°",
                     "ν",
                     "E / E_b");
  // Panels 160 units square from (90, 50), 190 apart: the second's last
  // grid point (bottom right) is gray, its first (top left) red.
  const auto gray = pixel("panels.png", 280 + 140, 50 + 140),
             red  = pixel("panels.png", 280 + 20, 50 + 20);
  deallog << "panels: undefined " << gray[0] << " " << gray[1] << " " << gray[2]
          << ", largest " << red[0] << " " << red[1] << " " << red[2]
          << "; panels.plot.csv: " << rows("panels.plot.csv").size() << " rows"
          << std::endl;

  // A raw image read back pixel for pixel.
  write_image("image.png", 2, 1, {255, 0, 0, 0, 128, 255});
  const auto a = pixel("image.png", 0, 0), b = pixel("image.png", 1, 0);
  deallog << "image: " << a[0] << " " << a[1] << " " << a[2] << " | " << b[0]
          << " " << b[1] << " " << b[2] << std::endl;

  // Fabrication outlines: an outer square with a square hole, as DXF.
  write_polygons_dxf("outline.dxf",
                     {{{{0, 0}}, {{10, 0}}, {{10, 10}}, {{0, 10}}},
                      {{{2, 2}}, {{2, 8}}, {{8, 8}}, {{8, 2}}}});
  std::istringstream dxf(read_file("outline.dxf"));
  unsigned int       polylines = 0, vertices = 0, closed = 0;
  std::string        code, value, last;
  double             x_sum = 0;
  while (std::getline(dxf, code) && std::getline(dxf, value))
    {
      if (code == "0")
        last = value;
      polylines += code == "0" && value == "POLYLINE";
      vertices += code == "0" && value == "VERTEX";
      closed += last == "POLYLINE" && code == "70" && value == "1";
      if (last == "VERTEX" && code == "10")
        x_sum += std::stod(value);
    }
  deallog << "outline.dxf: " << polylines << " polylines (" << closed
          << " closed), " << vertices << " vertices, sum of x " << x_sum
          << ", ends with EOF: " << (last == "EOF" ? "yes" : "no") << std::endl;

  // The data files redraw with matplotlib.
  for (const std::string csv : {"history.plot.csv",
                                "coverage.plot.csv",
                                "field.plot.csv",
                                "overlay.plot.csv",
                                "panels.plot.csv"})
    redraw(csv);

  // Bad input: a clear error and no file written.
  expect_refusal(
    "an unknown format",
    [&] { write_history_plot("h.jpg", values, "t", "x"); },
    "must end in .png, .svg or .pdf");
  expect_refusal(
    "a non-positive range on a log axis",
    [&] {
      write_xy_plot("bad.png",
                    {bound},
                    "t",
                    "x",
                    "y",
                    {{-1, 1}},
                    {{0, 1}},
                    {{false, true}});
    },
    "empty range [0, 1] on a logarithmic axis");
  expect_refusal(
    "an image of the wrong size",
    [] {
      write_image("bad.png", 2, 2, {1, 2, 3});
    },
    "3 bytes do not make a 2 x 2 RGB image");
  expect_refusal(
    "an image beyond Cairo's 32767 pixels",
    [] {
      write_image("bad.png", 40000, 1, std::vector<unsigned char>(3 * 40000));
    },
    "would be 40000 x 1 units");
  check("no bad.png written", !std::filesystem::exists("bad.png"));
  expect_refusal(
    "an unwritable directory",
    [&] { write_history_plot("no/such/dir/h.png", values, "t", "x"); },
    "cannot write the plot 'no/such/dir/h.png'");
  check("nothing left there", !std::filesystem::exists("no"));
}
