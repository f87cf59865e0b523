#include "plot_data.h"

#include <deal.II/base/exceptions.h>

#include <forma/base/replace_file.h>

#include <charconv>
#include <filesystem>
#include <fstream>

namespace forma
{
  namespace internal
  {
    std::string
    data_file_name(const std::string &plot_file)
    {
      return std::filesystem::path(plot_file)
        .replace_extension(".plot.csv")
        .string();
    }



    void
    write_plot_data(
      const std::string                                      &plot_file,
      const std::vector<std::pair<std::string, std::string>> &meta,
      const std::string                                      &header,
      const std::function<void(std::ostream &)>              &rows)
    {
      const std::string file = data_file_name(plot_file);
      replace_file(file, [&](const std::string &name) {
        std::ofstream out(name);
        for (const auto &[key, value] : meta)
          {
            // One line per entry, whatever the value holds.
            std::string line = value;
            for (char &c : line)
              if (c == '\n' || c == '\r')
                c = ' ';
            out << "# " << key << ": " << line << '\n';
          }
        out << header << '\n';
        rows(out);
        AssertThrow(out.flush(),
                    dealii::ExcMessage("cannot write the plot data '" + file +
                                       "'"));
      });
    }



    std::string
    number(const double v)
    {
      char       buffer[32];
      const auto end = std::to_chars(buffer, buffer + sizeof(buffer), v).ptr;
      return std::string(buffer, end);
    }



    std::string
    csv_quote(const std::string &s)
    {
      std::string q = "\"";
      for (const char c : s)
        q += (c == '"') ? std::string("\"\"") : std::string(1, c);
      return q + "\"";
    }
  } // namespace internal
} // namespace forma
