#include <deal.II/base/exceptions.h>
#include <deal.II/base/numbers.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <forma/base/plot.h>
#include <forma/base/run_context.h>
#include <forma/homogenization/coverage.h>
#include <forma/laminate/sweep_progress.h>

#include "modes.h"
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace forma
{
  namespace laminate
  {
    using namespace dealii;

    namespace
    {
      /// The homogenized samples of a sweep: n_fields values per structure.
      struct SampleTable
      {
        const std::vector<HexagonalLaminate> &structures;
        const std::vector<double>            &values;
        const Setup                          &setup;

        double
        operator()(const unsigned int k, const unsigned int field) const
        {
          return values[k * n_fields + field];
        }

        /// (nu, E/E_b) of sample k (E normalized by the base's 2D Young's
        /// modulus).
        std::array<double, 2>
        point(const unsigned int k) const
        {
          return {{(*this)(k, f_nu), (*this)(k, f_E) / setup.base.E}};
        }

        /**
         * Samples the grid does not resolve stay in samples.csv but not in
         * the coverage: thin beams or gaps (gray pixels bridge them, too
         * stiff), or an anisotropic result (every family structure is
         * isotropic, so anisotropy is discretization error, e.g. at the
         * acute hinges of chiral beams).
         */
        bool
        resolved(const unsigned int k) const
        {
          return (*this)(k, f_min_feature_cells) >= setup.min_feature_cells &&
                 (*this)(k, f_residual) <= setup.isotropy_tolerance;
        }

        /// The points of the samples `take` accepts.
        std::vector<std::array<double, 2>>
        points(const std::function<bool(unsigned int)> &take) const
        {
          std::vector<std::array<double, 2>> s;
          for (unsigned int k = 0; k < structures.size(); ++k)
            if (take(k))
              s.push_back(point(k));
          return s;
        }
      };



      void
      write_samples_csv(const std::string &file, const SampleTable &t)
      {
        std::ofstream csv(file);
        csv << "family,limit,p1,p2,p3,p4,theta,alpha_degrees,beams_per_joint,"
               "phi_formula,phi,E,nu,kappa,mu,a1,a2,isotropy_residual,"
               "hs_violation,C00,C01,C11,C22,min_feature_cells\n";
        csv << std::setprecision(std::numeric_limits<double>::max_digits10);
        for (unsigned int k = 0; k < t.structures.size(); ++k)
          {
            const auto &s = t.structures[k];
            csv << s.family_name() << ',' << s.limit << ',' << s.p1 << ','
                << (s.limit ? 0 : s.p2) << ',' << (s.limit ? 0 : s.p3) << ','
                << (s.limit ? 0 : s.p4) << ',' << (s.limit ? s.theta : 0) << ','
                << s.lamination_angle() * 180 / numbers::PI << ','
                << (s.limit ? 0 : 1 / s.p3);
            for (unsigned int f = 0; f < n_fields; ++f)
              csv << ',' << t(k, f);
            csv << '\n';
          }
      }



      /// Delta_L and Delta_R of the resolved samples, the HS check and
      /// eq. 5.10's fit: printed and in the summary.
      void
      report_coverage(const SampleTable &t,
                      const SweepGrid   &grid,
                      RunContext        &context)
      {
        const Setup &setup = t.setup;
        const auto   all =
          t.points([&](unsigned int k) { return t.resolved(k); });
        const auto coverage =
          coverage_coefficients(all, setup.base, grid.level, grid.band);
        const auto n_unresolved = t.structures.size() - all.size();
        if (n_unresolved > 0)
          context.print("coverage leaves out " + std::to_string(n_unresolved) +
                        " unresolved samples (beams, gaps or joints under " +
                        sig(setup.min_feature_cells) +
                        " cells, or isotropy residual over " +
                        sig(setup.isotropy_tolerance) + ")");
        double worst = -1e300, max_a = 0;
        for (unsigned int k = 0; k < t.structures.size(); ++k)
          {
            worst = std::max(worst, t(k, f_hs_violation));
            if (t.resolved(k))
              max_a = std::max(max_a, t(k, f_residual));
          }
        if (coverage.n_in_band == 0)
          context.print("coverage at E/Eb = " + sig(grid.level) +
                        ": no resolved sample within the band " +
                        sig(grid.band));
        else
          context.print("coverage at E/Eb = " + sig(grid.level) + ": nu from " +
                        sig(coverage.nu_left) + " to " +
                        sig(coverage.nu_right) + " (" +
                        std::to_string(coverage.n_in_band) +
                        " samples), Delta_L = " + sig(coverage.delta_left) +
                        ", Delta_R = " + sig(coverage.delta_right));
        context.print(
          std::string("all samples inside their Hashin-Shtrikman bounds: ") +
          (worst <= 0 ? "yes" : "NO") +
          "; largest isotropy residual of the resolved samples " +
          sig(max_a, 2));
        nlohmann::json &S                = context.summary;
        S["samples"]                     = t.structures.size();
        S["under_resolved_samples"]      = n_unresolved;
        S["grid"]                        = {grid_nx(setup.cells_along_height),
                                            setup.cells_along_height};
        S["coverage"]                    = {{"level", grid.level},
                                            {"band", grid.band},
                                            {"samples_in_band", coverage.n_in_band},
                                            {"nu_right", coverage.nu_right},
                                            {"nu_left", coverage.nu_left},
                                            {"limit_right", coverage.limit_right},
                                            {"limit_left", coverage.limit_left},
                                            {"delta_R", coverage.delta_right},
                                            {"delta_L", coverage.delta_left}};
        S["all_inside_hashin_shtrikman"] = worst <= 0;
        S["largest_hs_violation"]        = worst;
        S["largest_anisotropy"]          = max_a;
        const auto envelope              = upper_envelope(all, -1, 0, 20);
        if (envelope.size() >= 3)
          {
            const auto c             = fit_boundary_polynomial(envelope);
            S["boundary_polynomial"] = {{"c1", c[0]},
                                        {"c2", c[1]},
                                        {"c3", c[2]},
                                        {"envelope_points", envelope.size()}};
          }
      }



      /// Coverage per number of beams (Fig. 5.6C, 5.7A): in the summary,
      /// and coverage_by_beams.png.
      void
      report_coverage_by_beams(const SampleTable         &t,
                               const std::vector<double> &p3s,
                               const SweepGrid           &grid,
                               RunContext                &context)
      {
        std::vector<std::array<double, 2>> right, left;
        for (const double p3 : p3s)
          {
            const auto c = coverage_coefficients(t.points([&](unsigned int k) {
              return t.resolved(k) && t.structures[k].p3 == p3;
            }),
                                                 t.setup.base,
                                                 grid.level,
                                                 grid.band);
            context.summary["coverage_by_beams"].push_back(
              {{"beams", 1 / p3},
               {"delta_R", c.delta_right},
               {"delta_L", c.delta_left}});
            if (std::isfinite(c.delta_right))
              {
                right.push_back({{1 / p3, c.delta_right}});
                left.push_back({{1 / p3, c.delta_left}});
              }
          }
        if (context.is_root() && right.size() >= 2)
          {
            double n_max = 0;
            for (const auto &p : right)
              n_max = std::max(n_max, p[0]);
            write_xy_plot(context.path("coverage_by_beams.png"),
                          {{right, {{200, 60, 40}}, true, 2, "Δ_R"},
                           {left, {{31, 90, 180}}, true, 2, "Δ_L"},
                           {right, {{200, 60, 40}}, false, 3, ""},
                           {left, {{31, 90, 180}}, false, 3, ""}},
                          "Coverage vs beams per joint",
                          "beams per joint n",
                          "coverage Δ",
                          {{0, n_max * 1.05}},
                          {{0, 1.05}});
          }
      }



      /// The right Hashin-Shtrikman bound of volume fraction phi as a line.
      PlotSeries
      bound_curve(const Setup                       &setup,
                  const double                       phi,
                  const std::array<std::uint8_t, 3> &color,
                  const std::string                 &label)
      {
        const auto b = hashin_shtrikman(setup.base, setup.weak, phi);
        PlotSeries s;
        s.line = true, s.color = color, s.label = label;
        for (int k = 0; k <= 400; ++k)
          {
            const double nu = -1 + k / 200.;
            s.points.push_back({{nu, b.max_young_modulus(nu) / setup.base.E}});
          }
        return s;
      }



      /// coverage.png: (nu, E) against the HS bounds; samples colored by
      /// volume fraction band when it varies, by family otherwise.
      void
      write_coverage_plot(const std::string &file,
                          const SampleTable &t,
                          const SweepGrid   &grid)
      {
        const unsigned int n       = t.structures.size();
        double             phi_min = 1, phi_max = 0;
        for (unsigned int k = 0; k < n; ++k)
          {
            phi_min = std::min(phi_min, t(k, f_phi));
            phi_max = std::max(phi_max, t(k, f_phi));
          }
        const std::vector<std::array<std::uint8_t, 3>> colors = {
          {{200, 60, 40}},
          {{31, 90, 180}},
          {{40, 150, 60}},
          {{150, 70, 170}},
          {{230, 150, 20}}};
        std::vector<PlotSeries> series;
        if (phi_max - phi_min > 0.05)
          {
            const unsigned int n_bands = 4;
            for (unsigned int b = 0; b < n_bands; ++b)
              {
                const double lo = phi_min + (phi_max - phi_min) * b / n_bands,
                             hi = phi_min +
                                  (phi_max - phi_min) * (b + 1) / n_bands;
                PlotSeries s;
                s.color  = colors[b];
                s.label  = "φ " + sig(lo, 2) + "-" + sig(hi, 2);
                s.points = t.points([&](unsigned int k) {
                  const double phi = t(k, f_phi);
                  return t.resolved(k) && phi >= lo - 1e-12 &&
                         (phi < hi || b + 1 == n_bands);
                });
                series.push_back(s);
                series.push_back(bound_curve(t.setup, hi, colors[b], ""));
              }
          }
        else
          for (unsigned int f = 0; f < grid.families.size(); ++f)
            {
              PlotSeries s;
              s.color = colors[f];
              HexagonalLaminate named;
              named.family = grid.families[f];
              s.label      = named.family_name() + (grid.limit ? " limit" : "");
              s.points     = t.points([&](unsigned int k) {
                return t.resolved(k) &&
                       t.structures[k].family == grid.families[f];
              });
              series.push_back(s);
            }
        const auto unresolved =
          t.points([&](unsigned int k) { return !t.resolved(k); });
        if (!unresolved.empty())
          {
            PlotSeries s;
            s.color  = {{170, 170, 170}};
            s.label  = "unresolved";
            s.points = unresolved;
            series.insert(series.begin(), s);
          }
        series.push_back(
          bound_curve(t.setup, 1, {{0, 0, 0}}, "HS bound φ = 1"));
        if (phi_max - phi_min <= 0.05)
          series.push_back(bound_curve(t.setup,
                                       std::min(1., phi_min),
                                       {{120, 120, 120}},
                                       "HS bound φ = " + sig(phi_min, 3)));
        write_xy_plot(file,
                      series,
                      "Coverage of the HS bounds",
                      "Poisson's ratio ν",
                      "E / E_b",
                      {{-1, 1}},
                      {{0, 1.05}});
      }



      /// The settings a sweep's samples depend on (SweepProgress): the
      /// Base material, Grid and Sweep sections, but the coverage's level
      /// and band and Resume itself.
      std::map<std::string, std::string>
      sample_settings(ParameterHandler &prm)
      {
        std::ostringstream text;
        prm.print_parameters(text, ParameterHandler::JSON);
        const auto all = nlohmann::json::parse(text.str(), nullptr, false);
        std::map<std::string, std::string> settings;
        if (all.is_discarded()) // not UTF-8: the whole text stands for them
          return {{"parameters", text.str()}};
        for (const std::string section : {"Base material", "Grid", "Sweep"})
          for (const auto &[name, entry] : all.at(section).items())
            if (entry.is_object() && entry.contains("value") &&
                name != "Coverage level" && name != "Coverage band" &&
                name != "Resume")
              settings[section + "/" + name] = entry["value"];
        return settings;
      }
    } // namespace



    void
    sweep_mode(ParameterHandler &prm, const Setup &setup, RunContext &context)
    {
      const SweepGrid           grid = read_sweep_grid(prm);
      const SweepProgress       progress(context.persistent_path(
                                     "sweep_progress.csv"),
                                   sample_settings(prm),
                                   prm.get_bool({"Sweep"}, "Resume"),
                                   grid.structures.size(),
                                   n_fields,
                                   context);
      const std::vector<double> values = homogenize_all(
        grid.structures, setup, setup.cells_along_height, context, &progress);
      // Complete: a later run with Resume starts afresh.
      context.remove_on_commit("sweep_progress.csv");
      const SampleTable t{grid.structures, values, setup};
      if (context.is_root())
        write_samples_csv(context.path("samples.csv"), t);
      report_coverage(t, grid, context);
      const auto p3s = grid.values.find("p3");
      if (!grid.limit && p3s != grid.values.end() && p3s->second.size() > 1)
        report_coverage_by_beams(t, p3s->second, grid, context);
      if (context.is_root())
        write_coverage_plot(context.path("coverage.png"), t, grid);
    }
  } // namespace laminate
} // namespace forma
