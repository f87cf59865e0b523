#include "tiff_gray.h"

#include <deal.II/base/exceptions.h>

#include <tiffio.h>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <memory>

namespace forma
{
  namespace internal
  {
    namespace
    {
      // libtiff's messages for this file (the last error and warning).
      struct Messages
      {
        std::string error;
      };

      std::string
      format(const char *module, const char *fmt, va_list ap)
      {
        char text[400];
        std::vsnprintf(text, sizeof(text), fmt, ap);
        return (module ? std::string(module) + ": " : std::string()) + text;
      }

      int
      on_error(TIFF *,
               void       *user,
               const char *module,
               const char *fmt,
               va_list     ap)
      {
        static_cast<Messages *>(user)->error = format(module, fmt, ap);
        return 1; // handled: libtiff's default handler prints nothing
      }

      // Warnings (unknown tags and the like) do not stop the reading;
      // returning 1 keeps libtiff from printing them.
      int
      on_warning(TIFF *, void *, const char *, const char *, va_list)
      {
        return 1;
      }

      // 8192 x 8192 as for PNG: what one homogenization can hold.
      constexpr std::size_t max_pixels = std::size_t(1) << 26;

      // What the decoder needs to know of the first image.
      struct Layout
      {
        std::uint32_t width = 0, height = 0;
        std::uint16_t bits = 0, format = SAMPLEFORMAT_UINT;
        std::uint16_t stride       = 1; ///< samples a pixel in a row read
        bool          min_is_white = false, bottom_up = false;
      };

      Layout
      layout(TIFF *tiff, const std::string &file)
      {
        Layout        l;
        std::uint16_t samples = 1, photometric = PHOTOMETRIC_MINISBLACK,
                      planar = PLANARCONFIG_CONTIG, orientation = 1;
        TIFFGetField(tiff, TIFFTAG_IMAGEWIDTH, &l.width);
        TIFFGetField(tiff, TIFFTAG_IMAGELENGTH, &l.height);
        TIFFGetFieldDefaulted(tiff, TIFFTAG_SAMPLESPERPIXEL, &samples);
        TIFFGetFieldDefaulted(tiff, TIFFTAG_BITSPERSAMPLE, &l.bits);
        TIFFGetFieldDefaulted(tiff, TIFFTAG_SAMPLEFORMAT, &l.format);
        TIFFGetFieldDefaulted(tiff, TIFFTAG_PLANARCONFIG, &planar);
        TIFFGetFieldDefaulted(tiff, TIFFTAG_ORIENTATION, &orientation);
        TIFFGetField(tiff, TIFFTAG_PHOTOMETRIC, &photometric);
        const std::string in = "'" + file + "' ";
        AssertThrow(photometric == PHOTOMETRIC_MINISBLACK ||
                      photometric == PHOTOMETRIC_MINISWHITE,
                    dealii::ExcMessage(
                      in + "is a color or palette TIFF: save the structure as "
                           "a grayscale image (one density a pixel)"));
        const bool integer = l.format == SAMPLEFORMAT_UINT &&
                             (l.bits == 1 || l.bits == 2 || l.bits == 4 ||
                              l.bits == 8 || l.bits == 16);
        const bool real =
          l.format == SAMPLEFORMAT_IEEEFP && (l.bits == 32 || l.bits == 64);
        AssertThrow(integer || real,
                    dealii::ExcMessage(
                      in + "has " + std::to_string(l.bits) + "-bit " +
                      (l.format == SAMPLEFORMAT_INT    ? "signed" :
                       l.format == SAMPLEFORMAT_IEEEFP ? "float" :
                                                         "unsigned") +
                      " samples: use 1, 2, 4, 8 or 16-bit unsigned or "
                      "32/64-bit float gray"));
        AssertThrow(orientation == ORIENTATION_TOPLEFT ||
                      orientation == ORIENTATION_BOTLEFT,
                    dealii::ExcMessage(
                      in + "has orientation " + std::to_string(orientation) +
                      ": only rows from the top (1) or bottom (4), first "
                      "column left, are read"));
        AssertThrow(l.width > 0 && l.height > 0 &&
                      std::size_t(l.width) * l.height <= max_pixels,
                    dealii::ExcMessage(in + "is " + std::to_string(l.width) +
                                       " x " + std::to_string(l.height) +
                                       " pixels, more than 8192 x 8192"));
        // Gray and a few extra samples (alpha, masks) at most.
        AssertThrow(samples >= 1 && samples <= 8,
                    dealii::ExcMessage(in + "has " + std::to_string(samples) +
                                       " samples a pixel"));
        l.stride       = planar == PLANARCONFIG_CONTIG ? samples : 1;
        l.min_is_white = photometric == PHOTOMETRIC_MINISWHITE;
        l.bottom_up    = orientation == ORIENTATION_BOTLEFT;
        return l;
      }

      // Gray value of pixel i of a decoded row (host byte order), in [0, 1]
      // or NaN for a float outside it.
      double
      gray(const unsigned char *row, const std::size_t i, const Layout &l)
      {
        const std::size_t k = i * l.stride; // the pixel's first sample
        double            v = 0;
        if (l.format == SAMPLEFORMAT_IEEEFP)
          {
            if (l.bits == 32)
              {
                float f;
                std::memcpy(&f, row + 4 * k, 4);
                v = f;
              }
            else
              std::memcpy(&v, row + 8 * k, 8);
            if (!(v >= 0 && v <= 1))
              return std::nan("");
          }
        else if (l.bits == 16)
          {
            std::uint16_t s;
            std::memcpy(&s, row + 2 * k, 2);
            v = s / 65535.;
          }
        else // 1-8 bits, packed from the high bit
          {
            const std::size_t bit = k * l.bits;
            const unsigned    s   = row[bit / 8] >> (8 - l.bits - bit % 8);
            v = (s & ((1u << l.bits) - 1)) / double((1u << l.bits) - 1);
          }
        return l.min_is_white ? 1 - v : v;
      }

      // Decoded rows from strips or tiles, handed on as
      // (row, its y, first column, columns) pieces.
      template <typename Piece>
      void
      for_each_piece(TIFF              *tiff,
                     const Layout      &l,
                     const std::string &file,
                     const Messages    &messages,
                     const Piece       &piece)
      {
        const auto failed = [&](const std::string &where) {
          return dealii::ExcMessage("'" + file + "' is not a readable TIFF: " +
                                    where + ": " + messages.error);
        };
        // A header of a few bytes must not claim gigabytes of buffer.
        const auto buffer = [&](const tmsize_t bytes, const char *what) {
          AssertThrow(bytes > 0 && bytes <= (tmsize_t(1) << 28),
                      dealii::ExcMessage(
                        "'" + file + "': its " + what + " would take " +
                        std::to_string(bytes) + " bytes (at most 256 MiB)"));
          return std::vector<unsigned char>(bytes);
        };
        if (!TIFFIsTiled(tiff))
          {
            std::vector<unsigned char> row =
              buffer(TIFFScanlineSize(tiff), "row");
            for (std::uint32_t y = 0; y < l.height; ++y)
              {
                AssertThrow(TIFFReadScanline(tiff, row.data(), y, 0) >= 0,
                            failed("row " + std::to_string(y)));
                piece(row.data(), y, 0u, l.width);
              }
            return;
          }
        std::uint32_t tw = 0, th = 0;
        TIFFGetField(tiff, TIFFTAG_TILEWIDTH, &tw);
        TIFFGetField(tiff, TIFFTAG_TILELENGTH, &th);
        AssertThrow(tw > 0 && th > 0 && tw <= 8192 && th <= 8192,
                    dealii::ExcMessage("'" + file + "' has tiles of " +
                                       std::to_string(tw) + " x " +
                                       std::to_string(th) + " pixels"));
        std::vector<unsigned char> tile = buffer(TIFFTileSize(tiff), "tile");
        const std::size_t          row_bytes = TIFFTileRowSize(tiff);
        for (std::uint32_t y0 = 0; y0 < l.height; y0 += th)
          for (std::uint32_t x0 = 0; x0 < l.width; x0 += tw)
            {
              AssertThrow(TIFFReadTile(tiff, tile.data(), x0, y0, 0, 0) >= 0,
                          failed("tile at (" + std::to_string(x0) + ", " +
                                 std::to_string(y0) + ")"));
              for (std::uint32_t r = 0; r < th && y0 + r < l.height; ++r)
                piece(tile.data() + r * row_bytes,
                      y0 + r,
                      x0,
                      std::min(tw, l.width - x0));
            }
      }
    } // namespace



    std::vector<double>
    read_tiff_gray(const std::string &file,
                   unsigned int      &width,
                   unsigned int      &height)
    {
      Messages messages;
      const std::unique_ptr<TIFFOpenOptions, void (*)(TIFFOpenOptions *)>
        options(TIFFOpenOptionsAlloc(), TIFFOpenOptionsFree);
      TIFFOpenOptionsSetErrorHandlerExtR(options.get(), on_error, &messages);
      TIFFOpenOptionsSetWarningHandlerExtR(options.get(), on_warning, nullptr);
      // A corrupt header must not make libtiff take gigabytes.
      TIFFOpenOptionsSetMaxSingleMemAlloc(options.get(), 1 << 30);
      std::unique_ptr<TIFF, void (*)(TIFF *)> tiff(
        TIFFOpenExt(file.c_str(), "r", options.get()), TIFFClose);
      AssertThrow(tiff,
                  dealii::ExcMessage("'" + file + "' is not a readable TIFF: " +
                                     messages.error));
      const Layout l = layout(tiff.get(), file);
      width          = l.width;
      height         = l.height;
      std::vector<double> top_down(std::size_t(width) * height);
      for_each_piece(tiff.get(),
                     l,
                     file,
                     messages,
                     [&](const unsigned char *row,
                         const std::uint32_t  y,
                         const std::uint32_t  x0,
                         const std::uint32_t  n) {
                       const std::size_t top = l.bottom_up ? height - 1 - y : y;
                       for (std::uint32_t i = 0; i < n; ++i)
                         {
                           const double v = gray(row, i, l);
                           AssertThrow(!std::isnan(v),
                                       dealii::ExcMessage(
                                         "'" + file + "': the float at (" +
                                         std::to_string(x0 + i) + ", " +
                                         std::to_string(y) +
                                         ") is outside [0, 1]"));
                           top_down[top * width + x0 + i] = v;
                         }
                     });
      return top_down;
    }
  } // namespace internal
} // namespace forma
