#ifndef forma_microstructure_png_gray_h
#define forma_microstructure_png_gray_h

// Internal to density_image.cc: a PNG read as gray values in [0, 1].

#include <string>
#include <vector>

namespace forma
{
  namespace internal
  {
    /**
     * The gray values of a PNG, row by row from the top, each its sample
     * over the largest sample of its bit depth (1, 2, 4, 8 or 16 bits, read
     * exactly, no gamma applied). Color PNGs are refused (a density is one
     * number a pixel); alpha is dropped. Clear errors for files that are
     * not PNG, truncated or corrupt.
     */
    std::vector<double>
    read_png_gray(const std::string &file,
                  unsigned int      &width,
                  unsigned int      &height);
  } // namespace internal
} // namespace forma

#endif
