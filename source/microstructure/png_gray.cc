#include "png_gray.h"

#include <deal.II/base/exceptions.h>

#include <png.h>

#include <csetjmp>
#include <cstdio>
#include <cstring>

namespace forma
{
  namespace internal
  {
    namespace
    {
      // libpng reports errors by longjmp: the reader keeps its resources,
      // buffers and messages in a struct that outlives the jump (nothing
      // with a destructor lives only between setjmp and a jump).
      struct Reader
      {
        explicit Reader(const std::string &file)
          : file(std::fopen(file.c_str(), "rb"))
        {
          message[0] = warning[0] = '\0';
        }

        ~Reader()
        {
          if (png)
            png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
          if (file)
            std::fclose(file);
        }

        std::FILE                 *file;
        png_structp                png  = nullptr;
        png_infop                  info = nullptr;
        char                       message[200], warning[200];
        std::vector<unsigned char> pixels;
        std::vector<png_bytep>     rows;
      };

      void
      keep(char (&to)[200], png_const_charp text)
      {
        std::strncpy(to, text, sizeof(to) - 1);
        to[sizeof(to) - 1] = '\0';
      }

      void
      on_error(png_structp png, png_const_charp message)
      {
        keep(static_cast<Reader *>(png_get_error_ptr(png))->message, message);
        png_longjmp(png, 1);
      }

      // Kept for the error that may follow ("Invalid IHDR data" follows
      // the warning that says what is invalid).
      void
      on_warning(png_structp png, png_const_charp message)
      {
        keep(static_cast<Reader *>(png_get_error_ptr(png))->warning, message);
      }

      // 8192 x 8192: what one homogenization on a pixel grid can hold.
      constexpr std::size_t max_pixels = std::size_t(1) << 26;
    } // namespace



    std::vector<double>
    read_png_gray(const std::string &file_name,
                  unsigned int      &width,
                  unsigned int      &height)
    {
      Reader reader(file_name);
      AssertThrow(reader.file,
                  dealii::ExcMessage("cannot open the structure image '" +
                                     file_name + "'"));
      unsigned char signature[8] = {};
      AssertThrow(std::fread(signature, 1, 8, reader.file) == 8 &&
                    png_sig_cmp(signature, 0, 8) == 0,
                  dealii::ExcMessage(
                    "'" + file_name +
                    "' is not a PNG image (no PNG signature)"));
      reader.png = png_create_read_struct(PNG_LIBPNG_VER_STRING,
                                          &reader,
                                          on_error,
                                          on_warning);
      AssertThrow(reader.png,
                  dealii::ExcMessage("libpng: cannot create a reader (out of "
                                     "memory, or png.h and libpng differ)"));
      reader.info = png_create_info_struct(reader.png);
      AssertThrow(reader.info, dealii::ExcMessage("libpng: out of memory"));

      int color_type = 0, bit_depth = 0;
      if (setjmp(png_jmpbuf(reader.png)))
        AssertThrow(false,
                    dealii::ExcMessage(
                      "'" + file_name +
                      "' is not a readable PNG: " + reader.message +
                      (reader.warning[0] != '\0' ?
                         std::string(" (") + reader.warning + ")" :
                         std::string())));
      png_init_io(reader.png, reader.file);
      png_set_sig_bytes(reader.png, 8);
      png_set_user_limits(reader.png, 100000, 100000);
      png_read_info(reader.png, reader.info);
      width      = png_get_image_width(reader.png, reader.info);
      height     = png_get_image_height(reader.png, reader.info);
      color_type = png_get_color_type(reader.png, reader.info);
      bit_depth  = png_get_bit_depth(reader.png, reader.info);
      AssertThrow(!(color_type & PNG_COLOR_MASK_COLOR),
                  dealii::ExcMessage(
                    "'" + file_name +
                    "' is a color or palette PNG: save the structure as a "
                    "grayscale image (one density a pixel)"));
      AssertThrow(std::size_t(width) * height <= max_pixels,
                  dealii::ExcMessage(
                    "'" + file_name + "' is " + std::to_string(width) + " x " +
                    std::to_string(height) + " pixels, more than 8192 x 8192"));
      if (bit_depth < 8)
        png_set_expand_gray_1_2_4_to_8(reader.png);
      if (color_type & PNG_COLOR_MASK_ALPHA)
        png_set_strip_alpha(reader.png);
      png_set_interlace_handling(reader.png);
      png_read_update_info(reader.png, reader.info);
      const std::size_t row_bytes = png_get_rowbytes(reader.png, reader.info);
      reader.pixels.resize(row_bytes * height);
      reader.rows.resize(height);
      for (unsigned int y = 0; y < height; ++y)
        reader.rows[y] = reader.pixels.data() + y * row_bytes;
      png_read_image(reader.png, reader.rows.data());

      // 1, 2 and 4 bits come scaled to 8 (a 2-bit 3 is 255).
      const double        top = bit_depth == 16 ? 65535. : 255.;
      std::vector<double> gray(std::size_t(width) * height);
      for (std::size_t k = 0; k < gray.size(); ++k)
        gray[k] = (bit_depth == 16 ?
                     256. * reader.pixels[2 * k] + reader.pixels[2 * k + 1] :
                     double(reader.pixels[k])) /
                  top;
      return gray;
    }
  } // namespace internal
} // namespace forma
