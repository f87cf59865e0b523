#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <forma/base/application.h>
#include <forma/base/plot.h>
#include <forma/base/rank_strided.h>
#include <forma/base/run_context.h>
#include <forma/rhombic/redundant_parameters.h>

#include "modes.h"
#include <boost/serialization/map.hpp>
#include <boost/serialization/string.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    namespace
    {
      // Columns of a sample after its parameters.
      const std::vector<std::string> fields = {"phi",
                                               "E",
                                               "nu",
                                               "E1",
                                               "E2",
                                               "G12",
                                               "nu12",
                                               "a1",
                                               "a2",
                                               "isotropy_residual",
                                               "C00",
                                               "C01",
                                               "C11",
                                               "C22",
                                               "C02",
                                               "C12",
                                               "vertices",
                                               "dofs"};
      enum Field
      {
        f_phi,
        f_E,
        f_nu,
        f_E1,
        f_E2,
        f_G12,
        f_nu12,
        f_a1,
        f_a2
      };

      std::vector<double>
      sample_fields(const Sample &r)
      {
        const VoigtMatrix V = to_voigt(r.C);
        return {r.phi,
                r.fit.E,
                r.fit.nu,
                r.orthotropic.E1,
                r.orthotropic.E2,
                r.orthotropic.G12,
                r.orthotropic.nu12,
                r.anisotropy.a1,
                r.anisotropy.a2,
                r.anisotropy.residual,
                V[0][0],
                V[0][1],
                V[1][1],
                V[2][2],
                V[0][2],
                V[1][2],
                static_cast<double>(r.vertices),
                static_cast<double>(r.dofs)};
      }

      // The key of a structure in the progress file: its parameters.
      std::string
      key_of(const RhombicStructure &s)
      {
        std::ostringstream k;
        k << std::setprecision(12);
        for (const double p : s.p)
          k << p << ',';
        k << s.alpha * 180 / M_PI;
        return k.str();
      }

      struct Row
      {
        std::string         status = "ok";
        std::vector<double> values;
      };

      std::string
      csv_line(const RhombicStructure &s, const Row &row)
      {
        std::ostringstream line;
        line << std::setprecision(std::numeric_limits<double>::max_digits10)
             << key_of(s) << ',' << row.status;
        for (unsigned int f = 0; f < fields.size(); ++f)
          line << ','
               << (row.values.empty() ?
                     std::numeric_limits<double>::quiet_NaN() :
                     row.values[f]);
        return line.str();
      }

      std::string
      header()
      {
        std::string h = "p1,p2,p3,p4,p5,p6,p7,p8,angle_degrees,status";
        for (const auto &f : fields)
          h += "," + f;
        return h;
      }



      /// Every valid structure of the grid spanned by `values` (the
      /// parameters' lists, then the angles'); `skipped` counts the
      /// combinations out of range.
      std::vector<RhombicStructure>
      grid_structures(const std::vector<std::vector<double>> &values,
                      const double                            blending,
                      unsigned int                           &skipped)
      {
        std::vector<RhombicStructure> structures;
        std::vector<unsigned int>     index(values.size(), 0);
        skipped = 0;
        while (true)
          {
            RhombicStructure s;
            for (unsigned int i = 0; i < RhombicStructure::n_parameters; ++i)
              s.p[i] = values[i][index[i]];
            s.alpha    = values.back()[index.back()] * M_PI / 180;
            s.blending = blending;
            try
              {
                s.check();
                structures.push_back(s);
              }
            catch (const std::exception &)
              {
                // e.g. p1 + p2 too large: node 2 leaves its triangle
                ++skipped;
              }
            unsigned int d = 0;
            while (d < index.size() && ++index[d] == values[d].size())
              index[d++] = 0;
            if (d == index.size())
              return structures;
          }
      }



      /// The rows of an interrupted run's progress file by their keys
      /// (key_of()); root reads it for all ranks.
      std::map<std::string, std::string>
      read_progress(const std::string &progress, const RunContext &context)
      {
        std::map<std::string, std::string> done;
        if (context.is_root() && std::filesystem::exists(progress))
          {
            std::ifstream in(progress);
            std::string   line;
            std::getline(in, line); // header
            while (std::getline(in, line))
              {
                // The key is the first 9 fields.
                const auto parts = Utilities::split_string_list(line, ',');
                if (parts.size() != 10 + fields.size())
                  continue; // a line cut short by the interruption
                std::string key;
                for (unsigned int c = 0; c < 9; ++c)
                  key += (c > 0 ? "," : "") + parts[c];
                done[key] = line;
              }
          }
        return Utilities::MPI::broadcast(context.communicator(), done);
      }



      /// One structure's CSV row; a structure that cannot be homogenized
      /// (e.g. the material falls apart) is a result, not a failure.
      std::string
      evaluate_row(const RhombicStructure &s, const Setup &setup)
      {
        Row row;
        try
          {
            row.values = sample_fields(evaluate(s, setup, MPI_COMM_SELF));
          }
        catch (const std::exception &e)
          {
            std::string message = error_message(e);
            for (char &c : message)
              if (c == ',' || c == '\n')
                c = ';';
            row.status = "failed: " + message;
          }
        return csv_line(s, row);
      }



      /// Fill the empty rows of `lines` (one per structure) in batches
      /// shared among the ranks, appending each batch to the progress file
      /// (`done`: the rows it holds already).
      void
      compute_rows(const std::vector<RhombicStructure>      &structures,
                   const std::map<std::string, std::string> &done,
                   const std::string                        &progress,
                   const Setup                              &setup,
                   RunContext                               &context,
                   std::vector<std::string>                 &lines)
      {
        const unsigned int batch =
          progress_batch_size(structures.size(),
                              20,
                              Utilities::MPI::n_mpi_processes(
                                context.communicator()));
        for (unsigned int start = 0; start < structures.size(); start += batch)
          {
            const unsigned int end =
              std::min<unsigned int>(structures.size(), start + batch);
            std::vector<unsigned int> pending;
            for (unsigned int k = start; k < end; ++k)
              if (lines[k].empty())
                pending.push_back(k);
            const auto computed = rank_strided<std::string>(
              context.communicator(),
              pending.size(),
              [&](const unsigned int i) {
                return evaluate_row(structures[pending[i]], setup);
              });
            for (unsigned int i = 0; i < pending.size(); ++i)
              lines[pending[i]] = computed[i];
            if (context.is_root())
              {
                std::ofstream out(progress, std::ios::app);
                for (unsigned int k = start; k < end; ++k)
                  if (done.find(key_of(structures[k])) == done.end())
                    out << lines[k] << '\n';
              }
            context.print("sweep: " + std::to_string(end) + "/" +
                          std::to_string(structures.size()) + " structures");
          }
      }



      /// The rows parsed back: the samples in (nu, E/E_b) by isotropy, and
      /// the isotropic ones at the top angle for the redundancy test.
      struct SweepTable
      {
        unsigned int                       n_failed = 0;
        std::vector<std::array<double, 2>> isotropic, near_isotropic,
          anisotropic;
        double near_isotropy = 0;
        double E_min = 1e300, E_max = 0, nu_min = 1, nu_max = -1;
        std::vector<SweepPoint> isotropic_at_top;
      };



      SweepTable
      parse_rows(const std::vector<std::string> &lines,
                 const double                    top_angle,
                 const Setup                    &setup)
      {
        SweepTable t;
        t.near_isotropy = std::max(0.1, setup.isotropy_tolerance);
        for (const auto &line : lines)
          {
            const auto parts = Utilities::split_string_list(line, ',');
            AssertThrow(parts.size() == 10 + fields.size(),
                        ExcMessage("sweep: a malformed row in "
                                   "sweep_progress.csv: '" +
                                   line + "'"));
            if (parts[9] != "ok")
              {
                ++t.n_failed;
                continue;
              }
            std::vector<double> v;
            for (unsigned int f = 0; f < fields.size(); ++f)
              v.push_back(std::stod(parts[10 + f]));
            const double E = v[f_E] / setup.base.E, nu = v[f_nu];
            if (v[f_a1] <= setup.isotropy_tolerance &&
                v[f_a2] <= setup.isotropy_tolerance)
              {
                t.isotropic.push_back({{nu, E}});
                if (std::abs(std::stod(parts[8]) - top_angle) < 1e-9)
                  {
                    SweepPoint point;
                    for (unsigned int i = 0; i < 8; ++i)
                      point.p[i] = std::stod(parts[i]);
                    point.nu = nu, point.E = E;
                    t.isotropic_at_top.push_back(point);
                  }
                t.E_min  = std::min(t.E_min, E);
                t.E_max  = std::max(t.E_max, E);
                t.nu_min = std::min(t.nu_min, nu);
                t.nu_max = std::max(t.nu_max, nu);
              }
            else if (std::max(v[f_a1], v[f_a2]) <= t.near_isotropy)
              t.near_isotropic.push_back({{nu, E}});
            else
              t.anisotropic.push_back({{nu, E}});
          }
        return t;
      }



      /// coverage.png: every sample's isotropic fit, by isotropy.
      void
      write_coverage_plot(const std::string &file,
                          const SweepTable  &t,
                          const Setup       &setup)
      {
        double top = 0;
        for (const auto &s : {t.isotropic, t.near_isotropic, t.anisotropic})
          for (const auto &p : s)
            top = std::max(top, p[1]);
        PlotSeries all, near, iso;
        all.points  = t.anisotropic;
        all.color   = {{175, 175, 175}};
        all.label   = "isotropic fit, a₁ or a₂ > " + sig(t.near_isotropy);
        near.points = t.near_isotropic;
        near.color  = {{235, 150, 40}};
        near.label  = "a₁, a₂ ≤ " + sig(t.near_isotropy);
        iso.points  = t.isotropic;
        iso.color   = {{200, 30, 30}};
        iso.size    = 4;
        iso.label   = "a₁, a₂ ≤ " + sig(setup.isotropy_tolerance);
        write_xy_plot(file,
                      {all, near, iso},
                      "Rhombic family coverage",
                      "Poisson's ratio ν",
                      "E / E_b",
                      {{-1, 1}},
                      {{0, std::max(1e-3, 1.05 * top)}});
      }



      /// The ranges of all samples' and of the isotropic ones' moduli.
      void
      print_ranges(const SweepTable &t, const Setup &setup, RunContext &context)
      {
        double lo = 1e300, hi = -1e300, nlo = 1e300, nhi = -1e300;
        for (const auto &set : {t.isotropic, t.near_isotropic, t.anisotropic})
          for (const auto &p : set)
            {
              lo = std::min(lo, p[1]), hi = std::max(hi, p[1]);
              nlo = std::min(nlo, p[0]), nhi = std::max(nhi, p[0]);
            }
        if (t.isotropic.size() + t.near_isotropic.size() +
              t.anisotropic.size() >
            0)
          context.print("all samples (isotropic fit): E/E_b in [" + sig(lo) +
                        ", " + sig(hi) + "], nu in [" + sig(nlo) + ", " +
                        sig(nhi) + "]");
        context.print(
          "sweep: " + std::to_string(t.isotropic.size()) +
          " isotropic samples (a1, a2 <= " + sig(setup.isotropy_tolerance) +
          "), " + std::to_string(t.n_failed) + " failed");
        if (!t.isotropic.empty())
          context.print("isotropic coverage: E/E_b in [" + sig(t.E_min) + ", " +
                        sig(t.E_max) + "], nu in [" + sig(t.nu_min) + ", " +
                        sig(t.nu_max) + "]");
      }



      /// redundancy.png: the coverage of the expanding sets of fixed
      /// parameters.
      void
      write_redundancy_plot(const std::string                 &file,
                            const std::vector<FixedParameter> &fixings,
                            const SweepTable                  &t)
      {
        std::vector<PlotSeries> series(fixings.size() + 1);
        std::vector<SweepPoint> left = t.isotropic_at_top;
        const std::array<std::array<std::uint8_t, 3>, 4> colors = {
          {{{120, 60, 160}},
           {{40, 140, 60}},
           {{31, 90, 180}},
           {{200, 30, 30}}}};
        for (unsigned int k = 0; k <= fixings.size(); ++k)
          {
            if (k > 0)
              {
                std::vector<SweepPoint> slice;
                for (const auto &s : left)
                  if (s.p[fixings[k - 1].index] == fixings[k - 1].value)
                    slice.push_back(s);
                left = std::move(slice);
              }
            for (const auto &s : left)
              series[k].points.push_back({{s.nu, s.E}});
            series[k].color = colors[std::min<std::size_t>(k, 3)];
            series[k].size  = 4 - std::min<int>(k, 2);
            series[k].label =
              k == 0 ?
                "all parameters" :
                "+ " + RhombicStructure::parameter_name(fixings[k - 1].index) +
                  " = " + sig(fixings[k - 1].value);
          }
        write_xy_plot(file,
                      series,
                      "Coverage with fixed parameters",
                      "Poisson's ratio ν",
                      "E / E_b",
                      {{t.nu_min - 0.05, t.nu_max + 0.05}},
                      {{0, 1.1 * t.E_max}});
      }
    } // namespace



    void
    sweep_mode(ParameterHandler &prm, const Setup &setup, RunContext &context)
    {
      // The grid: every combination of the listed values.
      prm.enter_subsection("Sweep");
      std::vector<std::vector<double>> values;
      for (unsigned int i = 0; i < RhombicStructure::n_parameters; ++i)
        values.push_back(
          parse_values(prm.get(RhombicStructure::parameter_name(i)),
                       "Sweep/" + RhombicStructure::parameter_name(i)));
      values.push_back(parse_values(prm.get("Angles"), "Sweep/Angles"));
      const bool   resume = prm.get_bool("Resume");
      const double redundancy_threshold =
        prm.get_double("Redundancy threshold");
      prm.leave_subsection();

      unsigned int skipped  = 0;
      const auto structures = grid_structures(values, setup.blending, skipped);
      AssertThrow(!structures.empty(),
                  ExcMessage("Sweep: no valid structure in the parameter "
                             "grid (" +
                             std::to_string(skipped) +
                             " combinations are out of range)"));

      // Samples of an interrupted run.
      const std::string progress =
        context.persistent_path("sweep_progress.csv");
      const auto done = resume ? read_progress(progress, context) :
                                 std::map<std::string, std::string>();
      context.print("sweep: " + std::to_string(structures.size()) +
                    " structures" +
                    (skipped > 0 ? " (" + std::to_string(skipped) +
                                     " out-of-range combinations skipped)" :
                                   std::string()) +
                    (done.empty() ? std::string() :
                                    ", " + std::to_string(done.size()) +
                                      " taken from sweep_progress.csv"));
      std::vector<std::string> lines(structures.size());
      for (unsigned int k = 0; k < structures.size(); ++k)
        {
          const auto it = done.find(key_of(structures[k]));
          if (it != done.end())
            lines[k] = it->second;
        }
      if (context.is_root() && (!resume || !std::filesystem::exists(progress)))
        std::ofstream(progress) << header() << '\n';
      compute_rows(structures, done, progress, setup, context, lines);

      // Parse the rows back: one table for the CSV, plots and summary.
      const double top_angle =
        *std::max_element(values.back().begin(), values.back().end());
      const SweepTable t = parse_rows(lines, top_angle, setup);
      if (context.is_root())
        {
          std::ofstream csv(context.path("samples.csv"));
          csv << header() << '\n';
          for (const auto &line : lines)
            csv << line << '\n';
          write_coverage_plot(context.path("coverage.png"), t, setup);
        }
      print_ranges(t, setup, context);
      // The redundant-parameter test (thesis ch. 4.6.2, Fig. 4.9): which
      // parameters can be fixed without losing coverage.
      const auto fixings =
        find_redundant_parameters(t.isotropic_at_top, 12, redundancy_threshold);
      if (!t.isotropic_at_top.empty())
        {
          std::string line =
            "redundant parameters at " + sig(top_angle) +
            " degrees (coverage kept >= " + sig(redundancy_threshold) + "):";
          for (const auto &f : fixings)
            line += " " + RhombicStructure::parameter_name(f.index) + " = " +
                    sig(f.value) + " (" + sig(f.coverage, 3) + ", " +
                    std::to_string(f.samples) + " samples)";
          context.print(fixings.empty() ? line + " none" : line);
        }
      if (context.is_root() && !fixings.empty())
        write_redundancy_plot(context.path("redundancy.png"), fixings, t);
      nlohmann::json &S    = context.summary;
      S["samples"]         = structures.size();
      S["skipped"]         = skipped;
      S["failed"]          = t.n_failed;
      S["isotropic"]       = t.isotropic.size();
      S["resumed_samples"] = done.size();
      if (!t.isotropic.empty())
        S["isotropic_range"] = {{"E_min", t.E_min},
                                {"E_max", t.E_max},
                                {"nu_min", t.nu_min},
                                {"nu_max", t.nu_max}};
      for (const auto &f : fixings)
        S["redundant_parameters"].push_back(
          {{"parameter", RhombicStructure::parameter_name(f.index)},
           {"value", f.value},
           {"coverage", f.coverage},
           {"samples", f.samples}});
      // Complete: the progress file has served its purpose once the
      // results are in place.
      context.remove_on_commit("sweep_progress.csv");
    }
  } // namespace rhombic
} // namespace forma
