#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <forma/base/on_root.h>
#include <forma/base/replace_file.h>
#include <forma/base/run_context.h>
#include <forma/base/safe_text.h>
#include <forma/laminate/sweep_progress.h>

#include <boost/serialization/map.hpp>
#include <boost/serialization/vector.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

namespace forma
{
  namespace laminate
  {
    namespace
    {
      const std::string header_start = "# settings ";
      // The last field of a complete row: a row cut short by a kill inside
      // its last number would otherwise read as a whole one.
      const std::string row_end = "end";



      // Throws unless the header holds `settings`: the earlier run's
      // samples would not be this run's.
      void
      check_settings(const std::string                        &header,
                     const std::map<std::string, std::string> &settings,
                     const std::string                        &file)
      {
        const auto written =
          header.rfind(header_start, 0) == 0 ?
            nlohmann::json::parse(header.substr(header_start.size()),
                                  nullptr,
                                  false) :
            nlohmann::json(nlohmann::json::value_t::discarded);
        AssertThrow(written.is_object(),
                    dealii::ExcMessage("'" + file +
                                       "' is not a sweep progress file"));
        for (const auto &[entry, value] : settings)
          {
            const std::string before =
              written.contains(entry) && written[entry].is_string() ?
                written[entry].get<std::string>() :
                std::string("(not set)");
            AssertThrow(before == value,
                        dealii::ExcMessage(
                          "'" + file + "' holds the samples of a sweep with " +
                          entry + " = \"" + safe_text(before) + "\" (now \"" +
                          safe_text(value) +
                          "\"): resume with the same settings, or set "
                          "Resume = false"));
          }
      }



      // One finished structure's row "k,values...,end", or false for a row
      // cut short by the interruption (or of another sweep's size).
      bool
      parse_row(const std::string   &line,
                const unsigned int   n_structures,
                const unsigned int   n_values,
                unsigned int        &k,
                std::vector<double> &values)
      {
        auto parts = dealii::Utilities::split_string_list(line, ',');
        if (parts.size() != n_values + 2 || parts.back() != row_end ||
            parts[0].empty() || parts[0].size() > 9 ||
            parts[0].find_first_not_of("0123456789") != std::string::npos)
          return false;
        k = std::stoul(parts[0]);
        if (k >= n_structures)
          return false;
        values.resize(n_values);
        try
          {
            for (unsigned int i = 0; i < n_values; ++i)
              {
                std::size_t end = 0;
                values[i]       = std::stod(parts[i + 1], &end);
                if (end != parts[i + 1].size())
                  return false;
              }
          }
        catch (const std::exception &)
          {
            return false;
          }
        return true;
      }



      std::string
      row_text(const unsigned int k, const double *values, const unsigned int n)
      {
        std::ostringstream row;
        row << std::setprecision(std::numeric_limits<double>::max_digits10)
            << k;
        for (unsigned int i = 0; i < n; ++i)
          row << ',' << values[i];
        row << ',' << row_end << '\n';
        return row.str();
      }
    } // namespace



    SweepProgress::SweepProgress(
      const std::string                        &file,
      const std::map<std::string, std::string> &settings,
      const bool                                resume,
      const unsigned int                        n_structures,
      const unsigned int                        n_values,
      RunContext                               &context)
      : file(file)
      , n_values(n_values)
      , context(context)
    {
      // Settings that are not UTF-8 are written replaced (and then never
      // match: such a sweep does not resume).
      const std::string header =
        header_start +
        nlohmann::json(settings).dump(
          -1, ' ', false, nlohmann::json::error_handler_t::replace) +
        '\n';
      rows = on_root_or_throw(
        context.communicator(),
        [&]() {
          std::map<unsigned int, std::vector<double>> taken;
          std::string                                 text = header;
          if (resume && std::filesystem::exists(file))
            {
              std::ifstream in(file);
              std::string   line;
              std::getline(in, line);
              check_settings(line, settings, file);
              unsigned int        k;
              std::vector<double> values;
              while (std::getline(in, line))
                if (parse_row(line, n_structures, n_values, k, values))
                  taken[k] = values;
              for (const auto &[k, v] : taken)
                text += row_text(k, v.data(), n_values);
            }
          // Written whole (the rows kept, without a line the kill cut
          // short), so that the rows appended next start on a line of
          // their own.
          replace_file_text(file, text);
          return taken;
        },
        "Sweep/Resume");
    }



    const std::vector<double> *
    SweepProgress::done(const unsigned int k) const
    {
      const auto it = rows.find(k);
      return it == rows.end() ? nullptr : &it->second;
    }



    unsigned int
    SweepProgress::n_done() const
    {
      return rows.size();
    }



    void
    SweepProgress::append(const std::vector<unsigned int> &finished,
                          const std::vector<double>       &table) const
    {
      if (!context.is_root() || finished.empty())
        return;
      std::string lines;
      for (const unsigned int k : finished)
        lines += row_text(k, &table[k * n_values], n_values);
      std::ofstream out(file, std::ios::app);
      out << lines << std::flush;
      if (!out)
        context.log("sweep: progress not written to '" + file + "'");
    }
  } // namespace laminate
} // namespace forma
