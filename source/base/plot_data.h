#ifndef forma_base_plot_data_h
#define forma_base_plot_data_h

// Internal to plot.cc: the CSV beside each plot with exactly the plotted
// numbers, which contrib/plot/redraw.py reads to redraw the plot.

#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace forma
{
  namespace internal
  {
    /// `<stem>.plot.csv` for the plot `<stem>.<png|svg|pdf>` (apart from
    /// any table an app writes as `<stem>.csv`).
    std::string
    data_file_name(const std::string &plot_file);

    /**
     * Write the data file of `plot_file` whole: `# key: value` lines (the
     * first says what kind of plot), the column header, then the rows that
     * `rows` writes (numbers at full precision).
     */
    void
    write_plot_data(
      const std::string                                      &plot_file,
      const std::vector<std::pair<std::string, std::string>> &meta,
      const std::string                                      &header,
      const std::function<void(std::ostream &)>              &rows);

    /// The shortest text that reads back as exactly `v`.
    std::string
    number(const double v);

    /// A CSV field: quoted, quotes doubled.
    std::string
    csv_quote(const std::string &s);
  } // namespace internal
} // namespace forma

#endif
