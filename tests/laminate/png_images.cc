// Structure images as PNG: grayscale at 1, 2, 4, 8 and 16 bits, with alpha
// and interlaced, read exactly (each value over the largest of its depth,
// the top row of the file at the top of the cell); color PNGs, images over
// 8192 x 8192 pixels, bytes that are not PNG, truncated files and missing
// files refused with clear errors.

#include <forma/microstructure/density_image.h>

#include "../tests.h"
#include <png.h>

#include <cstdio>
#include <filesystem>

using namespace forma;
using dealii::deallog;

// A PNG file with its header written (the pixels would follow).
struct PngStart
{
  std::FILE  *file;
  png_structp png;
  png_infop   info;
};

PngStart
write_header(const std::string &name,
             const unsigned int w,
             const unsigned int h,
             const int          bit_depth,
             const int          color_type,
             const bool         interlaced)
{
  PngStart p;
  p.file = std::fopen(name.c_str(), "wb");
  p.png =
    png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  p.info = png_create_info_struct(p.png);
  png_init_io(p.png, p.file);
  png_set_IHDR(p.png,
               p.info,
               w,
               h,
               bit_depth,
               color_type,
               interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(p.png, p.info);
  return p;
}

void
close_png(PngStart &p)
{
  png_destroy_write_struct(&p.png, &p.info);
  std::fclose(p.file);
}

// Write a w x h PNG of `samples` (per pixel: gray, or gray and alpha, or
// RGB), rows from the top.
void
write_png(const std::string           &name,
          const unsigned int           w,
          const unsigned int           h,
          const int                    bit_depth,
          const int                    color_type,
          const bool                   interlaced,
          const std::vector<unsigned> &samples)
{
  PngStart    p   = write_header(name, w, h, bit_depth, color_type, interlaced);
  png_structp png = p.png;
  if (bit_depth < 8)
    png_set_packing(png); // one byte a sample in, packed bits out
  const unsigned int         per_pixel = samples.size() / (w * h);
  const unsigned int         bytes     = bit_depth == 16 ? 2 : 1;
  std::vector<unsigned char> data;
  for (const unsigned v : samples)
    {
      if (bytes == 2)
        data.push_back(v >> 8);
      data.push_back(v & 255);
    }
  std::vector<png_bytep> rows(h);
  for (unsigned int y = 0; y < h; ++y)
    rows[y] = data.data() + y * w * per_pixel * bytes;
  png_write_image(png, rows.data());
  png_write_end(png, nullptr);
  close_png(p);
}

// Read `name` and compare with the gray samples (every per_pixel-th from
// the first) over `top`, flipped to bottom-up rows.
void
check_exact(const std::string           &name,
            const unsigned int           w,
            const unsigned int           h,
            const unsigned int           per_pixel,
            const double                 top,
            const std::vector<unsigned> &samples)
{
  const DensityImage image = DensityImage::read(name, false);
  double             worst = image.nx == w && image.ny == h ? 0 : 1;
  for (unsigned int j = 0; j < h && worst == 0; ++j)
    for (unsigned int i = 0; i < w; ++i)
      worst =
        std::max(worst,
                 std::abs(image.density(i, j) -
                          samples[per_pixel * ((h - 1 - j) * w + i)] / top));
  deallog << name << ": " << image.nx << " x " << image.ny << ", mean "
          << image.mean() << ", exact: " << (worst == 0 ? "yes" : "NO")
          << std::endl;
}

int
main()
{
  initlog();
  // 3 x 2 images at every gray depth; the top row differs from the bottom.
  const std::vector<std::pair<int, std::vector<unsigned>>> depths = {
    {1, {1, 0, 1, 0, 0, 1}},
    {2, {0, 1, 2, 3, 3, 0}},
    {4, {0, 5, 15, 7, 9, 1}},
    {8, {0, 128, 255, 17, 200, 99}},
    {16, {0, 32768, 65535, 1, 40000, 12345}}};
  for (const auto &[bits, samples] : depths)
    {
      const std::string name = "gray" + std::to_string(bits) + ".png";
      write_png(name, 3, 2, bits, PNG_COLOR_TYPE_GRAY, false, samples);
      check_exact(name, 3, 2, 1, (1u << bits) - 1, samples);
    }
  // Gray and alpha, 8 bits: the alpha (the second sample) is ignored.
  const std::vector<unsigned> alpha = {
    0, 9, 128, 9, 255, 9, 17, 0, 200, 0, 99, 0};
  write_png("alpha.png", 3, 2, 8, PNG_COLOR_TYPE_GRAY_ALPHA, false, alpha);
  check_exact("alpha.png", 3, 2, 2, 255, alpha);
  // Interlaced (Adam7) 16 bits, 9 x 9 so that every pass has pixels.
  std::vector<unsigned> big(81);
  for (unsigned int k = 0; k < big.size(); ++k)
    big[k] = (k * 7919) % 65536;
  write_png("interlaced.png", 9, 9, 16, PNG_COLOR_TYPE_GRAY, true, big);
  check_exact("interlaced.png", 9, 9, 1, 65535, big);

  // Bad files.
  write_png("color.png",
            2,
            2,
            8,
            PNG_COLOR_TYPE_RGB,
            false,
            std::vector<unsigned>(12, 100));
  expect_refusal(
    "a color PNG",
    [] { DensityImage::read("color.png", false); },
    "is a color or palette PNG");
  {
    // The header of a 10000 x 10000 image: refused before any pixel memory
    // is taken.
    PngStart p =
      write_header("huge.png", 10000, 10000, 8, PNG_COLOR_TYPE_GRAY, false);
    close_png(p);
    // The start of the first IDAT chunk, where the header ends.
    std::ofstream("huge.png", std::ios::binary | std::ios::app)
      << std::string("\0\0\0\x10IDAT", 8) << "0123456789";
  }
  expect_refusal(
    "a PNG over 8192 x 8192 pixels",
    [] { DensityImage::read("huge.png", false); },
    "is 10000 x 10000 pixels, more than 8192 x 8192");
  std::ofstream("noise.png") << "GIF89a and then some bytes";
  expect_refusal(
    "not a PNG",
    [] { DensityImage::read("noise.png", false); },
    "is not a PNG image (no PNG signature)");
  const std::string whole = read_file("interlaced.png");
  std::ofstream("truncated.png", std::ios::binary)
    << whole.substr(0, whole.size() / 2);
  expect_refusal(
    "a truncated PNG",
    [] { DensityImage::read("truncated.png", false); },
    "'truncated.png' is not a readable PNG");
  expect_refusal(
    "a missing PNG",
    [] { DensityImage::read("nowhere.png", false); },
    "cannot open the structure image 'nowhere.png'");
  std::filesystem::copy_file("gray8.png",
                             "gray8.gif",
                             std::filesystem::copy_options::overwrite_existing);
  expect_refusal(
    "an unknown extension",
    [] { DensityImage::read("gray8.gif", false); },
    "use a .pgm, .png or .tif image");
}
