#include <deal.II/base/exceptions.h>
#include <deal.II/base/numbers.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <forma/base/plot.h>
#include <forma/base/run_context.h>
#include <forma/homogenization/coverage.h>

#include "modes.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace forma
{
  namespace laminate
  {
    using namespace dealii;

    void
    sweep_mode(ParameterHandler &prm, const Setup &setup, RunContext &context)
    {
      SweepGrid                 grid       = read_sweep_grid(prm);
      const auto               &families   = grid.families;
      const bool                limit      = grid.limit;
      auto                     &v          = grid.values;
      const auto               &structures = grid.structures;
      const double              level = grid.level, band = grid.band;
      const unsigned int        ny = setup.cells_along_height;
      const unsigned int        nx = grid_nx(ny);
      const std::vector<double> table =
        homogenize_all(structures, setup, ny, context);

      // CSV of all samples.
      if (context.is_root())
        {
          std::ofstream csv(context.path("samples.csv"));
          csv << "family,limit,p1,p2,p3,p4,theta,alpha_degrees,beams_per_joint,"
                 "phi_formula,phi,E,nu,kappa,mu,a1,a2,isotropy_residual,"
                 "hs_violation,C00,C01,C11,C22,min_feature_cells\n";
          csv << std::setprecision(std::numeric_limits<double>::max_digits10);
          for (unsigned int k = 0; k < structures.size(); ++k)
            {
              const auto &s = structures[k];
              csv << s.family_name() << ',' << s.limit << ',' << s.p1 << ','
                  << (s.limit ? 0 : s.p2) << ',' << (s.limit ? 0 : s.p3) << ','
                  << (s.limit ? 0 : s.p4) << ',' << (s.limit ? s.theta : 0)
                  << ',' << s.lamination_angle() * 180 / numbers::PI << ','
                  << (s.limit ? 0 : 1 / s.p3);
              for (unsigned int f = 0; f < n_fields; ++f)
                csv << ',' << table[k * n_fields + f];
              csv << '\n';
            }
        }

      // Coverage (E normalized by the base's 2D Young's modulus).
      auto samples_of = [&](const std::function<bool(unsigned int)> &take) {
        std::vector<std::array<double, 2>> s;
        for (unsigned int k = 0; k < structures.size(); ++k)
          if (take(k))
            s.push_back({{table[k * n_fields + f_nu],
                          table[k * n_fields + f_E] / setup.base.E}});
        return s;
      };
      // Samples the grid does not resolve stay in samples.csv but not in
      // the coverage: thin beams or gaps (gray pixels bridge them, too
      // stiff), or an anisotropic result (every family structure is
      // isotropic, so anisotropy is discretization error, e.g. at the
      // acute hinges of chiral beams).
      const auto resolved = [&](const unsigned int k) {
        return table[k * n_fields + f_min_feature_cells] >=
                 setup.min_feature_cells &&
               table[k * n_fields + f_residual] <= setup.isotropy_tolerance;
      };
      const auto all      = samples_of(resolved);
      const auto coverage = coverage_coefficients(all, setup.base, level, band);
      const auto n_unresolved = structures.size() - all.size();
      if (n_unresolved > 0)
        context.print("coverage leaves out " + std::to_string(n_unresolved) +
                      " unresolved samples (beams, gaps or joints under " +
                      sig(setup.min_feature_cells) +
                      " cells, or isotropy residual over " +
                      sig(setup.isotropy_tolerance) + ")");
      double worst = -1e300, max_a = 0;
      for (unsigned int k = 0; k < structures.size(); ++k)
        {
          worst = std::max(worst, table[k * n_fields + f_hs_violation]);
          if (resolved(k))
            max_a = std::max(max_a, table[k * n_fields + f_residual]);
        }
      if (coverage.n_in_band == 0)
        context.print("coverage at E/Eb = " + sig(level) +
                      ": no resolved sample within the band " + sig(band));
      else
        context.print("coverage at E/Eb = " + sig(level) + ": nu from " +
                      sig(coverage.nu_left) + " to " + sig(coverage.nu_right) +
                      " (" + std::to_string(coverage.n_in_band) +
                      " samples), Delta_L = " + sig(coverage.delta_left) +
                      ", Delta_R = " + sig(coverage.delta_right));
      context.print(
        std::string("all samples inside their Hashin-Shtrikman bounds: ") +
        (worst <= 0 ? "yes" : "NO") +
        "; largest isotropy residual of the resolved samples " + sig(max_a, 2));
      nlohmann::json &S                = context.summary;
      S["samples"]                     = structures.size();
      S["under_resolved_samples"]      = n_unresolved;
      S["grid"]                        = {nx, ny};
      S["coverage"]                    = {{"level", level},
                                          {"band", band},
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

      // Coverage per number of beams (Fig. 5.6C, 5.7A).
      std::vector<double> beam_counts;
      if (!limit && v["p3"].size() > 1)
        {
          std::vector<std::array<double, 2>> right, left;
          for (const double p3 : v["p3"])
            {
              const auto c =
                coverage_coefficients(samples_of([&](unsigned int k) {
                                        return resolved(k) &&
                                               structures[k].p3 == p3;
                                      }),
                                      setup.base,
                                      level,
                                      band);
              S["coverage_by_beams"].push_back({{"beams", 1 / p3},
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

      // (nu, E) coverage plot against the HS bounds; samples colored by
      // volume fraction band when it varies, by family otherwise.
      if (context.is_root())
        {
          double phi_min = 1, phi_max = 0;
          for (unsigned int k = 0; k < structures.size(); ++k)
            {
              phi_min = std::min(phi_min, table[k * n_fields + f_phi]);
              phi_max = std::max(phi_max, table[k * n_fields + f_phi]);
            }
          const std::vector<std::array<std::uint8_t, 3>> colors = {
            {{200, 60, 40}},
            {{31, 90, 180}},
            {{40, 150, 60}},
            {{150, 70, 170}},
            {{230, 150, 20}}};
          std::vector<PlotSeries> series;
          auto                    bound_curve = [&](const double                       phi,
                                 const std::array<std::uint8_t, 3> &c,
                                 const std::string                 &label) {
            const auto b = hashin_shtrikman(setup.base, setup.weak, phi);
            PlotSeries s;
            s.line = true, s.color = c, s.label = label;
            for (int k = 0; k <= 400; ++k)
              {
                const double nu = -1 + k / 200.;
                s.points.push_back(
                  {{nu, b.max_young_modulus(nu) / setup.base.E}});
              }
            return s;
          };
          if (phi_max - phi_min > 0.05)
            {
              const unsigned int n_bands = 4;
              for (unsigned int b = 0; b < n_bands; ++b)
                {
                  const double lo = phi_min + (phi_max - phi_min) * b / n_bands,
                               hi = phi_min +
                                    (phi_max - phi_min) * (b + 1) / n_bands;
                  PlotSeries s;
                  s.color = colors[b];
                  s.label = "φ " + sig(lo, 2) + "-" + sig(hi, 2);
                  for (unsigned int k = 0; k < structures.size(); ++k)
                    {
                      const double phi = table[k * n_fields + f_phi];
                      if (resolved(k) && phi >= lo - 1e-12 &&
                          (phi < hi || b + 1 == n_bands))
                        s.points.push_back(
                          {{table[k * n_fields + f_nu],
                            table[k * n_fields + f_E] / setup.base.E}});
                    }
                  series.push_back(s);
                  series.push_back(bound_curve(hi, colors[b], ""));
                }
            }
          else
            for (unsigned int f = 0; f < families.size(); ++f)
              {
                PlotSeries s;
                s.color = colors[f];
                HexagonalLaminate named;
                named.family = families[f];
                s.label      = named.family_name() + (limit ? " limit" : "");
                for (unsigned int k = 0; k < structures.size(); ++k)
                  if (resolved(k) && structures[k].family == families[f])
                    s.points.push_back(
                      {{table[k * n_fields + f_nu],
                        table[k * n_fields + f_E] / setup.base.E}});
                series.push_back(s);
              }
          if (n_unresolved > 0)
            {
              PlotSeries s;
              s.color = {{170, 170, 170}};
              s.label = "unresolved";
              for (unsigned int k = 0; k < structures.size(); ++k)
                if (!resolved(k))
                  s.points.push_back(
                    {{table[k * n_fields + f_nu],
                      table[k * n_fields + f_E] / setup.base.E}});
              series.insert(series.begin(), s);
            }
          series.push_back(bound_curve(1, {{0, 0, 0}}, "HS bound φ = 1"));
          if (phi_max - phi_min <= 0.05)
            series.push_back(bound_curve(std::min(1., phi_min),
                                         {{120, 120, 120}},
                                         "HS bound φ = " + sig(phi_min, 3)));
          write_xy_plot(context.path("coverage.png"),
                        series,
                        "Coverage of the HS bounds",
                        "Poisson's ratio ν",
                        "E / E_b",
                        {{-1, 1}},
                        {{0, 1.05}});
        }
    }
  } // namespace laminate
} // namespace forma
