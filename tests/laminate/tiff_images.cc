// Structure images as TIFF: grayscale at 1, 2, 4, 8 and 16 bits and as
// 32/64-bit floats, in strips and in tiles (partial edge tiles), raw and
// compressed (LZW, Deflate, PackBits), min-is-white inverted, alpha dropped
// (contiguous and planar), rows from the bottom, any case of the
// extension; each value read exactly (over the largest of its depth, the
// top row at the top of the cell). Color, palette and signed TIFFs, floats
// outside [0, 1], other orientations, images over 8192 x 8192 pixels,
// bytes that are not TIFF and truncated files are refused with clear
// errors.

#include <forma/microstructure/density_image.h>

#include "../tests.h"
#include <tiffio.h>

#include <cstring>
#include <functional>

using namespace forma;
using dealii::deallog;

// How to write a test TIFF of w x h pixels.
struct Format
{
  unsigned int  w = 3, h = 2;
  std::uint16_t bits = 8, format = SAMPLEFORMAT_UINT,
                photometric = PHOTOMETRIC_MINISBLACK, samples = 1,
                planar = PLANARCONFIG_CONTIG, compression = COMPRESSION_NONE,
                orientation = ORIENTATION_TOPLEFT;
  unsigned int tile         = 0; ///< tile edge (a multiple of 16), 0: strips
};

// Row y's samples from the top (file order, `planes` of them a pixel)
// packed as libtiff takes them.
std::vector<unsigned char>
pack(const Format              &f,
     const std::vector<double> &v,
     const unsigned int         y,
     const unsigned int         per_pixel,
     const unsigned int         first,
     const unsigned int         width)
{
  const unsigned int         n = width * per_pixel;
  std::vector<unsigned char> row((n * f.bits + 7) / 8 + 8, 0);
  for (unsigned int k = 0; k < n; ++k)
    {
      const double s =
        v[(y * f.w + first + k / per_pixel) * f.samples + k % per_pixel];
      if (f.format == SAMPLEFORMAT_IEEEFP && f.bits == 32)
        {
          const float x = s;
          std::memcpy(row.data() + 4 * k, &x, 4);
        }
      else if (f.format == SAMPLEFORMAT_IEEEFP)
        std::memcpy(row.data() + 8 * k, &s, 8);
      else if (f.bits == 16)
        {
          const std::uint16_t x = s;
          std::memcpy(row.data() + 2 * k, &x, 2);
        }
      else
        row[k * f.bits / 8] |= unsigned(s) << (8 - f.bits - k * f.bits % 8);
    }
  return row;
}

void
write_tiff(const std::string         &name,
           const Format              &f,
           const std::vector<double> &v)
{
  TIFF *t = TIFFOpen(name.c_str(), "w");
  TIFFSetField(t, TIFFTAG_IMAGEWIDTH, f.w);
  TIFFSetField(t, TIFFTAG_IMAGELENGTH, f.h);
  TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, f.bits);
  TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, f.format);
  TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, f.samples);
  TIFFSetField(t, TIFFTAG_PHOTOMETRIC, f.photometric);
  TIFFSetField(t, TIFFTAG_PLANARCONFIG, f.planar);
  TIFFSetField(t, TIFFTAG_COMPRESSION, f.compression);
  TIFFSetField(t, TIFFTAG_ORIENTATION, f.orientation);
  if (f.samples > 1 && f.photometric != PHOTOMETRIC_RGB)
    {
      const std::uint16_t alpha = EXTRASAMPLE_UNASSALPHA;
      TIFFSetField(t, TIFFTAG_EXTRASAMPLES, 1, &alpha);
    }
  const bool         contiguous = f.planar == PLANARCONFIG_CONTIG;
  const unsigned int per_pixel  = contiguous ? f.samples : 1;
  const unsigned int planes     = contiguous ? 1 : f.samples;
  // A plane's samples alone (planar images store one plane after another).
  const auto plane = [&](const unsigned int s) {
    if (contiguous)
      return v;
    std::vector<double> p(v.size() * f.samples, 0);
    for (unsigned int k = 0; k < f.w * f.h; ++k)
      p[k * f.samples] = v[k * f.samples + s];
    return p;
  };
  if (f.tile == 0)
    {
      TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, 1u);
      for (unsigned int s = 0; s < planes; ++s)
        for (unsigned int y = 0; y < f.h; ++y)
          TIFFWriteScanline(t,
                            pack(f, plane(s), y, per_pixel, 0, f.w).data(),
                            y,
                            s);
    }
  else
    {
      TIFFSetField(t, TIFFTAG_TILEWIDTH, f.tile);
      TIFFSetField(t, TIFFTAG_TILELENGTH, f.tile);
      std::vector<unsigned char> tile(TIFFTileSize(t), 0);
      const std::size_t          row_bytes = TIFFTileRowSize(t);
      for (unsigned int y0 = 0; y0 < f.h; y0 += f.tile)
        for (unsigned int x0 = 0; x0 < f.w; x0 += f.tile)
          {
            std::fill(tile.begin(), tile.end(), 0);
            const unsigned int n = std::min(f.tile, f.w - x0);
            for (unsigned int r = 0; r < f.tile && y0 + r < f.h; ++r)
              {
                const auto row = pack(f, v, y0 + r, per_pixel, x0, n);
                std::memcpy(tile.data() + r * row_bytes,
                            row.data(),
                            std::min(row.size(), row_bytes));
              }
            TIFFWriteTile(t, tile.data(), x0, y0, 0, 0);
          }
    }
  TIFFClose(t);
}

// Read `name` and compare with the first sample of each pixel over `top`
// (inverted for min-is-white), rows from the top of the file unless
// bottom-up.
void
check_exact(const std::string         &name,
            const Format              &f,
            const std::vector<double> &v,
            const double               top)
{
  const DensityImage image = DensityImage::read(name, false);
  double             worst = image.nx == f.w && image.ny == f.h ? 0 : 1;
  const bool         white = f.photometric == PHOTOMETRIC_MINISWHITE;
  const bool         up    = f.orientation == ORIENTATION_BOTLEFT;
  for (unsigned int j = 0; j < f.h && worst == 0; ++j)
    for (unsigned int i = 0; i < f.w; ++i)
      {
        const unsigned int y = up ? j : f.h - 1 - j; // file row
        const double       s = v[(y * f.w + i) * f.samples] / top;
        worst =
          std::max(worst, std::abs(image.density(i, j) - (white ? 1 - s : s)));
      }
  deallog << name << ": " << image.nx << " x " << image.ny << ", mean "
          << image.mean() << ", exact: " << (worst == 0 ? "yes" : "NO")
          << std::endl;
}

// w x h samples (per pixel `samples`) counting through [0, top].
std::vector<double>
ramp(const Format &f, const double top)
{
  std::vector<double> v(f.w * f.h * f.samples);
  for (unsigned int k = 0; k < v.size(); ++k)
    v[k] = top >= 1 ? double((k * 7919) % (unsigned(top) + 1)) : (k % 11) / 10.;
  return v;
}

void
exact(const std::string &name, const Format &f, const double top)
{
  const std::vector<double> v = ramp(f, top);
  write_tiff(name, f, v);
  check_exact(name, f, v, top);
}

int
main()
{
  initlog();
  for (const std::uint16_t bits : {1, 2, 4, 8, 16})
    {
      Format f;
      f.bits = bits;
      exact("gray" + std::to_string(bits) + ".tif", f, (1u << bits) - 1);
    }
  Format f;
  f.photometric = PHOTOMETRIC_MINISWHITE;
  exact("min_is_white.tif", f, 255);
  f             = Format();
  f.w           = 40;
  f.h           = 35;
  f.bits        = 16;
  f.tile        = 16;
  f.compression = COMPRESSION_LZW;
  exact("tiled_lzw.tif", f, 65535);
  f             = Format();
  f.format      = SAMPLEFORMAT_IEEEFP;
  f.bits        = 32;
  f.compression = COMPRESSION_ADOBE_DEFLATE;
  exact("float32_deflate.tif", f, 1);
  f.bits = 64;
  exact("float64.TIFF", f, 1);
  f             = Format();
  f.samples     = 2;
  f.compression = COMPRESSION_PACKBITS;
  exact("alpha.tif", f, 255);
  f.planar = PLANARCONFIG_SEPARATE;
  exact("alpha_planar.tif", f, 255);
  f             = Format();
  f.orientation = ORIENTATION_BOTLEFT;
  exact("bottom_up.tif", f, 255);

  // Bad files.
  const auto refused = [](const std::string         &what,
                          const std::string         &name,
                          const Format              &f,
                          const std::vector<double> &v,
                          const std::string         &message) {
    write_tiff(name, f, v);
    expect_refusal(
      what, [&] { DensityImage::read(name, false); }, message);
  };
  f             = Format();
  f.samples     = 3;
  f.photometric = PHOTOMETRIC_RGB;
  refused(
    "an RGB TIFF", "rgb.tif", f, ramp(f, 255), "is a color or palette TIFF");
  f        = Format();
  f.format = SAMPLEFORMAT_INT;
  f.bits   = 16;
  refused("a signed TIFF",
          "signed.tif",
          f,
          ramp(f, 100),
          "has 16-bit signed samples");
  f                     = Format();
  f.format              = SAMPLEFORMAT_IEEEFP;
  f.bits                = 32;
  std::vector<double> v = ramp(f, 1);
  v[4]                  = 1.5; // (1, 1) from the top
  refused("a float outside [0, 1]",
          "float_range.tif",
          f,
          v,
          "the float at (1, 1) is outside [0, 1]");
  f             = Format();
  f.orientation = ORIENTATION_LEFTTOP;
  refused("a transposed TIFF",
          "transposed.tif",
          f,
          ramp(f, 255),
          "has orientation 5");
  f      = Format();
  f.w    = 10000;
  f.h    = 10000;
  f.tile = 16;
  {
    // The header of a 10000 x 10000 image with its first tile only.
    TIFF *t = TIFFOpen("huge.tif", "w");
    TIFFSetField(t, TIFFTAG_IMAGEWIDTH, f.w);
    TIFFSetField(t, TIFFTAG_IMAGELENGTH, f.h);
    TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, 8);
    TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    TIFFSetField(t, TIFFTAG_TILEWIDTH, 16);
    TIFFSetField(t, TIFFTAG_TILELENGTH, 16);
    std::vector<unsigned char> tile(256, 0);
    TIFFWriteTile(t, tile.data(), 0, 0, 0, 0);
    TIFFClose(t);
  }
  expect_refusal(
    "a TIFF over 8192 x 8192 pixels",
    [] { DensityImage::read("huge.tif", false); },
    "is 10000 x 10000 pixels, more than 8192 x 8192");
  std::ofstream("noise.tif") << "GIF89a and then some bytes";
  expect_refusal(
    "not a TIFF",
    [] { DensityImage::read("noise.tif", false); },
    "'noise.tif' is not a readable TIFF");
  const std::string whole = read_file("tiled_lzw.tif");
  std::ofstream("truncated.tif", std::ios::binary)
    << whole.substr(0, whole.size() / 2);
  expect_refusal(
    "a truncated TIFF",
    [] { DensityImage::read("truncated.tif", false); },
    "'truncated.tif' is not a readable TIFF");
  expect_refusal(
    "a missing TIFF",
    [] { DensityImage::read("nowhere.tif", false); },
    "cannot open the structure image 'nowhere.tif'");
}
