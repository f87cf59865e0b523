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

      std::vector<RhombicStructure> structures;
      unsigned int                  skipped = 0;
      std::vector<unsigned int>     index(values.size(), 0);
      while (true)
        {
          RhombicStructure s;
          for (unsigned int i = 0; i < RhombicStructure::n_parameters; ++i)
            s.p[i] = values[i][index[i]];
          s.alpha    = values.back()[index.back()] * M_PI / 180;
          s.blending = setup.blending;
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
            break;
        }
      AssertThrow(!structures.empty(),
                  ExcMessage("Sweep: no valid structure in the parameter "
                             "grid (" +
                             std::to_string(skipped) +
                             " combinations are out of range)"));

      // Samples of an interrupted run.
      const std::string progress =
        context.persistent_path("sweep_progress.csv");
      std::map<std::string, std::string> done;
      if (resume && context.is_root() && std::filesystem::exists(progress))
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
      done = Utilities::MPI::broadcast(context.communicator(), done);

      const unsigned int n_ranks =
        Utilities::MPI::n_mpi_processes(context.communicator());
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
      if (context.is_root() && !resume)
        std::ofstream(progress) << header() << '\n';
      else if (context.is_root() && !std::filesystem::exists(progress))
        std::ofstream(progress) << header() << '\n';

      const unsigned int batch =
        progress_batch_size(structures.size(), 20, n_ranks);
      for (unsigned int start = 0; start < structures.size(); start += batch)
        {
          const unsigned int end =
            std::min<unsigned int>(structures.size(), start + batch);
          std::vector<unsigned int> pending;
          for (unsigned int k = start; k < end; ++k)
            if (lines[k].empty())
              pending.push_back(k);
          const auto computed = rank_strided<std::string>(
            context.communicator(), pending.size(), [&](const unsigned int i) {
              const unsigned int k = pending[i];
              Row                row;
              try
                {
                  row.values = sample_fields(
                    evaluate(structures[k], setup, MPI_COMM_SELF));
                }
              catch (const std::exception &e)
                {
                  // A structure that cannot be homogenized (e.g. the
                  // material falls apart) is a result, not a failure.
                  std::string message = error_message(e);
                  for (char &c : message)
                    if (c == ',' || c == '\n')
                      c = ';';
                  row.status = "failed: " + message;
                }
              return csv_line(structures[k], row);
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

      // Parse the rows back: one table for the CSV, plots and summary.
      unsigned int                       n_failed = 0, n_isotropic = 0;
      std::vector<std::array<double, 2>> isotropic, near_isotropic, anisotropic;
      const double near_isotropy = std::max(0.1, setup.isotropy_tolerance);
      double       E_min = 1e300, E_max = 0, nu_min = 1, nu_max = -1;
      const double top_angle =
        *std::max_element(values.back().begin(), values.back().end());
      std::vector<SweepPoint> isotropic_at_top; // for the redundancy test
      for (const auto &line : lines)
        {
          const auto parts = Utilities::split_string_list(line, ',');
          AssertThrow(parts.size() == 10 + fields.size(),
                      ExcMessage("sweep: a malformed row in "
                                 "sweep_progress.csv: '" +
                                 line + "'"));
          if (parts[9] != "ok")
            {
              ++n_failed;
              continue;
            }
          std::vector<double> v;
          for (unsigned int f = 0; f < fields.size(); ++f)
            v.push_back(std::stod(parts[10 + f]));
          const double E = v[f_E] / setup.base.E, nu = v[f_nu];
          if (v[f_a1] <= setup.isotropy_tolerance &&
              v[f_a2] <= setup.isotropy_tolerance)
            {
              ++n_isotropic;
              isotropic.push_back({{nu, E}});
              if (std::abs(std::stod(parts[8]) - top_angle) < 1e-9)
                {
                  SweepPoint point;
                  for (unsigned int i = 0; i < 8; ++i)
                    point.p[i] = std::stod(parts[i]);
                  point.nu = nu, point.E = E;
                  isotropic_at_top.push_back(point);
                }
              E_min = std::min(E_min, E), E_max = std::max(E_max, E);
              nu_min = std::min(nu_min, nu), nu_max = std::max(nu_max, nu);
            }
          else if (std::max(v[f_a1], v[f_a2]) <= near_isotropy)
            near_isotropic.push_back({{nu, E}});
          else
            anisotropic.push_back({{nu, E}});
        }
      if (context.is_root())
        {
          std::ofstream csv(context.path("samples.csv"));
          csv << header() << '\n';
          for (const auto &line : lines)
            csv << line << '\n';
          double top = 0;
          for (const auto &s : {isotropic, near_isotropic, anisotropic})
            for (const auto &p : s)
              top = std::max(top, p[1]);
          PlotSeries all, near, iso;
          all.points  = anisotropic;
          all.color   = {{175, 175, 175}};
          all.label   = "isotropic fit, a₁ or a₂ > " + sig(near_isotropy);
          near.points = near_isotropic;
          near.color  = {{235, 150, 40}};
          near.label  = "a₁, a₂ ≤ " + sig(near_isotropy);
          iso.points  = isotropic;
          iso.color   = {{200, 30, 30}};
          iso.size    = 4;
          iso.label   = "a₁, a₂ ≤ " + sig(setup.isotropy_tolerance);
          write_xy_plot(context.path("coverage.png"),
                        {all, near, iso},
                        "Rhombic family coverage",
                        "Poisson's ratio ν",
                        "E / E_b",
                        {{-1, 1}},
                        {{0, std::max(1e-3, 1.05 * top)}});
        }
      {
        double lo = 1e300, hi = -1e300, nlo = 1e300, nhi = -1e300;
        for (const auto &set : {isotropic, near_isotropic, anisotropic})
          for (const auto &p : set)
            {
              lo = std::min(lo, p[1]), hi = std::max(hi, p[1]);
              nlo = std::min(nlo, p[0]), nhi = std::max(nhi, p[0]);
            }
        if (isotropic.size() + near_isotropic.size() + anisotropic.size() > 0)
          context.print("all samples (isotropic fit): E/E_b in [" + sig(lo) +
                        ", " + sig(hi) + "], nu in [" + sig(nlo) + ", " +
                        sig(nhi) + "]");
      }
      context.print(
        "sweep: " + std::to_string(n_isotropic) +
        " isotropic samples (a1, a2 <= " + sig(setup.isotropy_tolerance) +
        "), " + std::to_string(n_failed) + " failed");
      if (n_isotropic > 0)
        context.print("isotropic coverage: E/E_b in [" + sig(E_min) + ", " +
                      sig(E_max) + "], nu in [" + sig(nu_min) + ", " +
                      sig(nu_max) + "]");
      // The redundant-parameter test (thesis ch. 4.6.2, Fig. 4.9): which
      // parameters can be fixed without losing coverage.
      const auto fixings =
        find_redundant_parameters(isotropic_at_top, 12, redundancy_threshold);
      if (!isotropic_at_top.empty())
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
        {
          // The coverage of the expanding sets of fixed parameters.
          std::vector<PlotSeries> series(fixings.size() + 1);
          std::vector<SweepPoint> left = isotropic_at_top;
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
                  "+ " +
                    RhombicStructure::parameter_name(fixings[k - 1].index) +
                    " = " + sig(fixings[k - 1].value);
            }
          write_xy_plot(context.path("redundancy.png"),
                        series,
                        "Coverage with fixed parameters",
                        "Poisson's ratio ν",
                        "E / E_b",
                        {{nu_min - 0.05, nu_max + 0.05}},
                        {{0, 1.1 * E_max}});
        }
      nlohmann::json &S    = context.summary;
      S["samples"]         = structures.size();
      S["skipped"]         = skipped;
      S["failed"]          = n_failed;
      S["isotropic"]       = n_isotropic;
      S["resumed_samples"] = done.size();
      if (n_isotropic > 0)
        S["isotropic_range"] = {{"E_min", E_min},
                                {"E_max", E_max},
                                {"nu_min", nu_min},
                                {"nu_max", nu_max}};
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
