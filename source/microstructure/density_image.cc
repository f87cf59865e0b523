#include <deal.II/base/exceptions.h>

#include <forma/microstructure/density_image.h>

#include "png_gray.h"
#include "tiff_gray.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>

namespace forma
{
  using namespace dealii;

  namespace
  {
    // Next whitespace-separated token of a PGM header, skipping comments.
    std::string
    pgm_token(std::istream &in, const std::string &file)
    {
      std::string token;
      while (in >> token)
        {
          if (token[0] != '#')
            return token;
          std::string rest;
          std::getline(in, rest);
        }
      AssertThrow(false,
                  ExcMessage("'" + file + "' ends inside its PGM header"));
      return token;
    }

    // ".png" of "Cell.PNG"; empty without one.
    std::string
    lowercase_extension(const std::string &file)
    {
      std::string extension = std::filesystem::path(file).extension().string();
      for (char &c : extension)
        c = std::tolower(static_cast<unsigned char>(c));
      return extension;
    }

    unsigned int
    pgm_number(std::istream &in, const std::string &file, const char *what)
    {
      const std::string token = pgm_token(in, file);
      AssertThrow(!token.empty() &&
                    std::all_of(token.begin(), token.end(), ::isdigit),
                  ExcMessage("'" + file + "': the PGM " + what + " '" + token +
                             "' is not a positive integer"));
      return std::stoul(token);
    }
  } // namespace



  double
  DensityImage::mean() const
  {
    return values.empty() ?
             0 :
             std::accumulate(values.begin(), values.end(), 0.) / values.size();
  }



  DensityImage
  DensityImage::read(const std::string &file, const bool invert)
  {
    std::ifstream in(file, std::ios::binary);
    AssertThrow(in,
                ExcMessage("cannot open the structure image '" + file + "'"));
    DensityImage        image;
    std::vector<double> top_down;
    const std::string   extension = lowercase_extension(file);
    if (extension == ".pgm")
      {
        std::string magic;
        in >> magic;
        AssertThrow(magic == "P2" || magic == "P5",
                    ExcMessage(
                      "'" + file +
                      "' is not a grayscale PGM image (it starts with '" +
                      magic.substr(0, 8) + "', not P2 or P5)"));
        image.nx                     = pgm_number(in, file, "width");
        image.ny                     = pgm_number(in, file, "height");
        const unsigned int max_value = pgm_number(in, file, "maximum value");
        // 8192 x 8192 as for PNG: what one homogenization can hold.
        AssertThrow(image.nx > 0 && image.ny > 0 && image.nx <= 8192 &&
                      image.ny <= 8192 && max_value > 0 && max_value < 65536,
                    ExcMessage("'" + file + "': PGM size " +
                               std::to_string(image.nx) + " x " +
                               std::to_string(image.ny) + ", maximum " +
                               std::to_string(max_value) + " is not valid"));
        const std::size_t n = std::size_t(image.nx) * image.ny;
        top_down.resize(n);
        if (magic == "P2")
          for (std::size_t k = 0; k < n; ++k)
            {
              long v = -1;
              AssertThrow(in >> v,
                          ExcMessage("'" + file + "' has " + std::to_string(k) +
                                     " gray values, its header promises " +
                                     std::to_string(n)));
              AssertThrow(v >= 0 && v <= long(max_value),
                          ExcMessage("'" + file + "': gray value " +
                                     std::to_string(v) + " is outside [0, " +
                                     std::to_string(max_value) + "]"));
              top_down[k] = double(v) / max_value;
            }
        else
          {
            in.get(); // the single whitespace after the header
            const unsigned int         bytes = max_value < 256 ? 1 : 2;
            std::vector<unsigned char> raw(n * bytes);
            in.read(reinterpret_cast<char *>(raw.data()), raw.size());
            AssertThrow(std::size_t(in.gcount()) == raw.size(),
                        ExcMessage("'" + file + "' is truncated: " +
                                   std::to_string(in.gcount()) + " of " +
                                   std::to_string(raw.size()) +
                                   " pixel bytes"));
            for (std::size_t k = 0; k < n; ++k)
              {
                const unsigned int v =
                  bytes == 1 ? raw[k] : 256u * raw[2 * k] + raw[2 * k + 1];
                AssertThrow(v <= max_value,
                            ExcMessage("'" + file + "': gray value " +
                                       std::to_string(v) +
                                       " exceeds the "
                                       "maximum " +
                                       std::to_string(max_value)));
                top_down[k] = double(v) / max_value;
              }
          }
      }
    else if (extension == ".png")
      top_down = internal::read_png_gray(file, image.nx, image.ny);
    else if (extension == ".tif" || extension == ".tiff")
      top_down = internal::read_tiff_gray(file, image.nx, image.ny);
    else if (extension == ".csv")
      {
        std::string  line;
        unsigned int line_number = 0;
        while (std::getline(in, line))
          {
            ++line_number;
            std::replace(line.begin(), line.end(), ',', ' ');
            std::istringstream  row(line);
            std::vector<double> values;
            std::string         token;
            while (row >> token)
              {
                std::size_t used = 0;
                double      v    = 0;
                try
                  {
                    v = std::stod(token, &used);
                  }
                catch (...)
                  {
                    used = 0;
                  }
                AssertThrow(used == token.size(),
                            ExcMessage("'" + file + "' line " +
                                       std::to_string(line_number) + ": '" +
                                       token + "' is not a number"));
                AssertThrow(v >= 0 && v <= 1,
                            ExcMessage("'" + file + "' line " +
                                       std::to_string(line_number) +
                                       ": density " + token +
                                       " is outside [0, 1]"));
                values.push_back(v);
              }
            if (values.empty())
              continue;
            if (image.nx == 0)
              image.nx = values.size();
            AssertThrow(values.size() == image.nx,
                        ExcMessage("'" + file + "' line " +
                                   std::to_string(line_number) + " has " +
                                   std::to_string(values.size()) +
                                   " values, the first row has " +
                                   std::to_string(image.nx)));
            top_down.insert(top_down.end(), values.begin(), values.end());
            ++image.ny;
          }
      }
    else
      AssertThrow(false,
                  ExcMessage(
                    "structure image '" + file +
                    "': use a .pgm, .png or .tif image or a .csv matrix"));
    AssertThrow(image.nx >= 2 && image.ny >= 2,
                ExcMessage("structure image '" + file + "' has " +
                           std::to_string(image.nx) + " x " +
                           std::to_string(image.ny) +
                           " pixels; at least 2 x 2 are needed"));
    image.values.resize(top_down.size());
    for (unsigned int j = 0; j < image.ny; ++j)
      for (unsigned int i = 0; i < image.nx; ++i)
        {
          const double v = top_down[(image.ny - 1 - j) * image.nx + i];
          image.values[j * image.nx + i] = invert ? 1 - v : v;
        }
    return image;
  }
} // namespace forma
