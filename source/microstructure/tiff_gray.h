#ifndef forma_microstructure_tiff_gray_h
#define forma_microstructure_tiff_gray_h

// Internal to density_image.cc: a TIFF read as gray values in [0, 1].

#include <string>
#include <vector>

namespace forma
{
  namespace internal
  {
    /**
     * The gray values of the first image of a TIFF, row by row from the
     * top: unsigned samples of 1, 2, 4, 8 or 16 bits over the largest of
     * their depth, or 32/64-bit floats that must lie in [0, 1];
     * min-is-white images inverted to min-is-black. Strips or tiles, any
     * compression libtiff decodes; extra samples (alpha) are dropped.
     * Color and palette TIFFs are refused (a density is one number a
     * pixel), as are files that are not TIFF, truncated or corrupt, with
     * libtiff's reason in the message.
     */
    std::vector<double>
    read_tiff_gray(const std::string &file,
                   unsigned int      &width,
                   unsigned int      &height);
  } // namespace internal
} // namespace forma

#endif
