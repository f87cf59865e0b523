#include <deal.II/base/exceptions.h>

#include <forma/base/outline.h>
#include <forma/base/replace_file.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <iomanip>

namespace forma
{
  namespace
  {
    using Polygons = std::vector<std::vector<std::array<double, 2>>>;

    void
    write_whole(const std::string                         &file_name,
                const std::function<void(std::ostream &)> &write)
    {
      replace_file(file_name, [&](const std::string &name) {
        std::ofstream out(name);
        out << std::setprecision(9);
        write(out);
        AssertThrow(out.flush(),
                    dealii::ExcMessage("cannot write the outline '" +
                                       file_name + "'"));
      });
    }
  } // namespace



  void
  write_polygons_svg(const std::string &file_name,
                     const Polygons    &polygons,
                     const double       stroke)
  {
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (const auto &polygon : polygons)
      for (const auto &v : polygon)
        for (unsigned int d = 0; d < 2; ++d)
          {
            lo[d] = std::min(lo[d], v[d]);
            hi[d] = std::max(hi[d], v[d]);
          }
    AssertThrow(hi[0] >= lo[0],
                dealii::ExcMessage("the outline '" + file_name +
                                   "' has no polygons"));
    const double pad = 2 * stroke;
    // One unit is one millimetre (cutters read unitless sizes as pixels).
    const double w = hi[0] - lo[0] + 2 * pad, h = hi[1] - lo[1] + 2 * pad;
    write_whole(file_name, [&](std::ostream &out) {
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
    });
  }



  void
  write_polygons_dxf(const std::string &file_name, const Polygons &polygons)
  {
    // DXF is pairs of lines: a group code, then its value.
    write_whole(file_name, [&](std::ostream &out) {
      const auto group = [&](const int code, const auto &value) {
        out << code << '\n' << value << '\n';
      };
      group(0, "SECTION");
      group(2, "HEADER");
      group(9, "$ACADVER");
      group(1, "AC1009");
      group(0, "ENDSEC");
      group(0, "SECTION");
      group(2, "ENTITIES");
      for (const auto &polygon : polygons)
        {
          group(0, "POLYLINE");
          group(8, "outline");
          group(66, 1); // vertices follow
          group(70, 1); // closed
          group(10, 0.);
          group(20, 0.);
          group(30, 0.);
          for (const auto &v : polygon)
            {
              group(0, "VERTEX");
              group(8, "outline");
              group(10, v[0]);
              group(20, v[1]);
              group(30, 0.);
            }
          group(0, "SEQEND");
          group(8, "outline");
        }
      group(0, "ENDSEC");
      group(0, "EOF");
    });
  }
} // namespace forma
