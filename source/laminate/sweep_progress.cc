#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <forma/base/on_root.h>
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
      // cut short by the interruption.
      bool
      parse_row(const std::string   &line,
                unsigned int        &k,
                std::vector<double> &values)
      {
        auto parts = dealii::Utilities::split_string_list(line, ',');
        if (parts.size() < 3 || parts.back() != row_end)
          return false;
        parts.pop_back();
        try
          {
            std::size_t end = 0;
            k               = std::stoul(parts[0], &end);
            if (end != parts[0].size())
              return false;
            values.clear();
            for (std::size_t i = 1; i < parts.size(); ++i)
              {
                values.push_back(std::stod(parts[i], &end));
                if (end != parts[i].size())
                  return false;
              }
          }
        catch (const std::exception &)
          {
            return false;
          }
        return true;
      }
    } // namespace



    SweepProgress::SweepProgress(
      const std::string                        &file,
      const std::map<std::string, std::string> &settings,
      const bool                                resume,
      RunContext                               &context)
      : file(file)
      , context(context)
    {
      namespace fs = std::filesystem;
      rows         = on_root_or_throw(
        context.communicator(),
        [&]() {
          std::map<unsigned int, std::vector<double>> taken;
          if (resume && fs::exists(file))
            {
              std::ifstream in(file);
              std::string   line;
              std::getline(in, line);
              check_settings(line, settings, file);
              unsigned int        k;
              std::vector<double> values;
              while (std::getline(in, line))
                if (parse_row(line, k, values))
                  taken[k] = values;
              return taken;
            }
          std::ofstream out(file);
          // Settings that are not UTF-8 are written replaced (and then
          // never match: such a sweep does not resume).
          out << header_start
              << nlohmann::json(settings).dump(
                   -1, ' ', false, nlohmann::json::error_handler_t::replace)
              << '\n';
          AssertThrow(out, dealii::ExcMessage("cannot write '" + file + "'"));
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
                          const std::vector<double>       &table,
                          const unsigned int               n_values) const
    {
      if (!context.is_root() || finished.empty())
        return;
      std::ostringstream lines;
      lines << std::setprecision(std::numeric_limits<double>::max_digits10);
      for (const unsigned int k : finished)
        {
          lines << k;
          for (unsigned int i = 0; i < n_values; ++i)
            lines << ',' << table[k * n_values + i];
          lines << ',' << row_end << '\n';
        }
      std::ofstream out(file, std::ios::app);
      out << lines.str() << std::flush;
      if (!out)
        context.log("sweep: progress not written to '" + file + "'");
    }
  } // namespace laminate
} // namespace forma
