#ifndef forma_base_plot_h
#define forma_base_plot_h

#include <string>
#include <vector>

namespace forma
{
  /**
   * Write a PNG line plot of `values` against their index (iterations, time
   * steps): a logarithmic y axis of values / values[0] when every value is
   * positive, a linear one otherwise. Small and dependency-free apart from
   * zlib, so every app can leave a picture of its convergence next to its
   * numbers.
   */
  void
  write_history_plot(const std::string         &file_name,
                     const std::vector<double> &values,
                     const std::string         &title,
                     const std::string         &x_label);
} // namespace forma

#endif
