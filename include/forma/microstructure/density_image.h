#ifndef forma_microstructure_density_image_h
#define forma_microstructure_density_image_h

#include <string>
#include <vector>

namespace forma
{
  /**
   * A user's structure as a matrix of densities in [0, 1] (1 = base
   * material, 0 = void), read from a grayscale PGM image (P2 or P5; gray
   * value / max value, white = solid unless inverted), a grayscale PNG
   * (1 to 16 bits; value / largest value of its depth, no gamma), a
   * grayscale TIFF (the first image; 1 to 16 bits as PNG, or floats in
   * [0, 1]) or a CSV file (one image row per line, comma or whitespace
   * separated). Row 0 of the file
   * is the top of the cell, as in an image; `density(i, j)` counts j from
   * the bottom.
   */
  struct DensityImage
  {
    unsigned int        nx = 0, ny = 0;
    std::vector<double> values; ///< row-major from the bottom row

    double
    density(const unsigned int i, const unsigned int j) const
    {
      return values[j * nx + i];
    }

    double
    mean() const;

    /// Reads by extension (.pgm, .png, .tif/.tiff or .csv, any case); clear
    /// errors for malformed files, values outside [0, 1] and ragged rows.
    static DensityImage
    read(const std::string &file_name, const bool invert);
  };
} // namespace forma

#endif
