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
      // libpng reports errors by longjmp: the reader keeps its resources
      // and the message in a plain struct that outlives the jump.
      struct Reader
      {
        explicit Reader(const std::string &file)
          : file(std::fopen(file.c_str(), "rb"))
        {
          message[0] = '\0';
        }

        ~Reader()
        {
          if (png)
            png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
          if (file)
            std::fclose(file);
        }

        std::FILE  *file;
        png_structp png  = nullptr;
        png_infop   info = nullptr;
        char        message[200];
      };

      void
      on_error(png_structp png, png_const_charp message)
      {
        auto *reader = static_cast<Reader *>(png_get_error_ptr(png));
        std::strncpy(reader->message, message, sizeof(reader->message) - 1);
        reader->message[sizeof(reader->message) - 1] = '\0';
        png_longjmp(png, 1);
      }

      void
      on_warning(png_structp, png_const_charp)
      {}
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
      AssertThrow(reader.png, dealii::ExcMessage("libpng: out of memory"));
      reader.info = png_create_info_struct(reader.png);
      AssertThrow(reader.info, dealii::ExcMessage("libpng: out of memory"));

      std::vector<unsigned char> pixels; // alive across the jump
      std::vector<png_bytep>     rows;
      int                        color_type = 0, bit_depth = 0;
      if (setjmp(png_jmpbuf(reader.png)))
        AssertThrow(false,
                    dealii::ExcMessage(
                      "'" + file_name +
                      "' is not a readable PNG: " + reader.message));
      png_init_io(reader.png, reader.file);
      png_set_sig_bytes(reader.png, 8);
      png_set_user_limits(reader.png, 100000, 100000);
      png_read_info(reader.png, reader.info);
      width      = png_get_image_width(reader.png, reader.info);
      height     = png_get_image_height(reader.png, reader.info);
      color_type = png_get_color_type(reader.png, reader.info);
      bit_depth  = png_get_bit_depth(reader.png, reader.info);
      if (!(color_type & PNG_COLOR_MASK_COLOR))
        {
          if (bit_depth < 8)
            png_set_expand_gray_1_2_4_to_8(reader.png);
          if (color_type & PNG_COLOR_MASK_ALPHA)
            png_set_strip_alpha(reader.png);
          png_set_interlace_handling(reader.png);
          png_read_update_info(reader.png, reader.info);
          const std::size_t row_bytes =
            png_get_rowbytes(reader.png, reader.info);
          pixels.resize(row_bytes * height);
          rows.resize(height);
          for (unsigned int y = 0; y < height; ++y)
            rows[y] = pixels.data() + y * row_bytes;
          png_read_image(reader.png, rows.data());
        }
      AssertThrow(!(color_type & PNG_COLOR_MASK_COLOR),
                  dealii::ExcMessage(
                    "'" + file_name +
                    "' is a color PNG: save the structure as a grayscale "
                    "image (one density a pixel)"));

      // 1, 2 and 4 bits come scaled to 8 (a 2-bit 3 is 255).
      const double        top = bit_depth == 16 ? 65535. : 255.;
      std::vector<double> gray(std::size_t(width) * height);
      for (std::size_t k = 0; k < gray.size(); ++k)
        gray[k] = (bit_depth == 16 ? 256. * pixels[2 * k] + pixels[2 * k + 1] :
                                     double(pixels[k])) /
                  top;
      return gray;
    }
  } // namespace internal
} // namespace forma
