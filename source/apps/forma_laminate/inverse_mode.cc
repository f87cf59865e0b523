#include <deal.II/base/exceptions.h>
#include <deal.II/base/numbers.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>
#include <deal.II/grid/tria.h>

#include <forma/base/application.h>
#include <forma/base/run_context.h>
#include <forma/laminate/shape_derivative.h>
#include <forma/optimization/optimizer.h>

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

    namespace
    {
      /// One row of a sample table: a structure and its (E, nu).
      struct TableSample
      {
        HexagonalLaminate structure;
        double            E = 0, nu = 0;
      };

      /// The samples of a sweep's samples.csv (columns found by name).
      std::vector<TableSample>
      read_sample_table(const std::string &file)
      {
        std::ifstream in(file);
        AssertThrow(in,
                    ExcMessage("Inverse/Table file: cannot open '" + file +
                               "'"));
        std::string line;
        std::getline(in, line);
        const auto names = Utilities::split_string_list(line);
        std::map<std::string, unsigned int> column;
        for (unsigned int c = 0; c < names.size(); ++c)
          column[names[c]] = c;
        for (const char *name : {"family",
                                 "limit",
                                 "p1",
                                 "p2",
                                 "p3",
                                 "p4",
                                 "theta",
                                 "alpha_degrees",
                                 "E",
                                 "nu"})
          AssertThrow(column.count(name),
                      ExcMessage("Inverse/Table file '" + file +
                                 "' has no column '" + name +
                                 "' (expected the samples.csv of a sweep)"));
        std::vector<TableSample> table;
        unsigned int             row = 1;
        while (std::getline(in, line))
          {
            ++row;
            if (Utilities::trim(line).empty())
              continue;
            const auto f = Utilities::split_string_list(line);
            AssertThrow(
              f.size() == names.size(),
              ExcMessage("Inverse/Table file '" + file + "', line " +
                         std::to_string(row) + ": " + std::to_string(f.size()) +
                         " fields, expected " + std::to_string(names.size())));
            TableSample t;
            try
              {
                auto value = [&](const char *name) {
                  return std::stod(f[column[name]]);
                };
                auto &s = t.structure;
                s.family =
                  HexagonalLaminate::family_from_string(f[column["family"]]);
                s.limit = value("limit") != 0;
                s.p1    = value("p1");
                if (s.limit)
                  s.theta = value("theta"),
                  s.alpha = value("alpha_degrees") * numbers::PI / 180;
                else
                  s.p2 = value("p2"), s.p3 = value("p3"), s.p4 = value("p4");
                t.E  = value("E");
                t.nu = value("nu");
                s.check();
              }
            catch (const std::exception &e)
              {
                AssertThrow(false,
                            ExcMessage("Inverse/Table file '" + file +
                                       "', line " + std::to_string(row) + ": " +
                                       error_message(e)));
              }
            table.push_back(t);
          }
        AssertThrow(!table.empty(),
                    ExcMessage("Inverse/Table file '" + file +
                               "' has no samples"));
        return table;
      }

      /**
       * Thesis Table 5.1's row for one iterate: the structure meshed
       * conformingly, its compliance misfit and the norm of its shape
       * derivative on the solid-void interface, and where it concentrates.
       */
      nlohmann::json
      shape_derivative_row(const HexagonalLaminate &s,
                           const Setup             &setup,
                           const double             size,
                           const unsigned int       degree,
                           const ComplianceMisfit  &misfit)
      {
        Triangulation<2> mesh;
        conforming_mesh(s, size, mesh);
        std::vector<double> density;
        const auto phases = phase_tensors(s, setup.base, setup.weak, density);
        const auto d      = interface_shape_derivative(
          mesh, phases, setup.weak.tensor(), setup.solver, degree, misfit);
        const auto fit = isotropic_fit(d.C);
        return {{"mesh_J", d.J},
                {"mesh_E_over_Eb", fit.E / setup.base.E},
                {"mesh_nu", fit.nu},
                {"cells", d.n_cells},
                {"interface_vertices", d.vertices.size()},
                {"shape_derivative_norm", d.norm},
                {"corner_share", corner_share(d, s, size)}};
      }
    } // namespace



    /**
     * Inverse design: the structure of a family whose (E, nu) is a target.
     * The nearest samples of a table (a sweep's samples.csv, or the Sweep grid
     * homogenized here on a coarse grid) start bound-constrained L-BFGS runs
     * (ROL, optimize()) on J = (E/E* - 1)^2 + (nu - nu*)^2 over the
     * continuous parameters (p1, p2, p4 or p1, theta, alpha; p3 keeps its
     * beam count) at the Grid resolution. The anti-aliased rasterization is
     * exact in areas, so E and nu are continuous, piecewise smooth functions
     * of the parameters, and their gradient is exact (evaluate_gradient():
     * AD through the rasterization, C^H's self-adjoint material gradient).
     */
    void
    inverse_mode(ParameterHandler  &prm,
                 const std::string &prm_directory,
                 const Setup       &setup,
                 RunContext        &context)
    {
      prm.enter_subsection("Inverse");
      const double       target_E   = prm.get_double("Target Young's modulus");
      const double       target_nu  = prm.get_double("Target Poisson's ratio");
      std::string        table_file = prm.get("Table file");
      const unsigned int table_ny = prm.get_integer("Table cells along height");
      const unsigned int n_candidates = prm.get_integer("Candidates");
      OptimizationParameters op;
      op.max_iterations                 = prm.get_integer("Max iterations");
      const double tolerance            = prm.get_double("Tolerance");
      const bool   compliance_objective = prm.get("Objective") == "compliance";
      const bool   report_shape = prm.get_bool("Report shape derivative");
      prm.leave_subsection();
      AssertThrow(!report_shape || compliance_objective,
                  ExcMessage("Inverse/Report shape derivative needs "
                             "Inverse/Objective = compliance (thesis Table "
                             "5.1's objective)."));
      prm.enter_subsection("Conforming mesh");
      const double       mesh_size   = prm.get_double("Element size");
      const unsigned int mesh_degree = prm.get_integer("Degree");
      prm.leave_subsection();
      op.value_target       = compliance_objective ?
                                -std::numeric_limits<double>::infinity() :
                                tolerance * tolerance;
      op.relative_decrease  = 1e-6;
      op.decrease_window    = 3;
      op.gradient_tolerance = 1e-8;
      op.print_iterations   = false;
      // E is relative to the base's 2D Young's modulus.
      const double E_star = target_E * setup.base.E;
      {
        const auto hs = hashin_shtrikman(setup.base, setup.weak, 1);
        AssertThrow(E_star <= hs.max_young_modulus(target_nu) &&
                      target_nu > -1 && target_nu < 1,
                    ExcMessage(
                      "Inverse: the target (E/Eb, nu) = (" + sig(target_E) +
                      ", " + sig(target_nu) +
                      ") lies outside the Hashin-Shtrikman bounds "
                      "(E/Eb <= " +
                      sig(hs.max_young_modulus(target_nu) / setup.base.E) +
                      " at this nu): no structure reaches it"));
      }
      const SweepGrid grid = read_sweep_grid(prm);

      // The table: given, or the Sweep grid on a coarse grid.
      std::vector<TableSample> table;
      if (!table_file.empty())
        {
          if (table_file[0] != '/')
            table_file = prm_directory + "/" + table_file;
          table = read_sample_table(table_file);
          context.print("inverse: " + std::to_string(table.size()) +
                        " samples from the table file");
        }
      else
        {
          const auto values =
            homogenize_all(grid.structures, setup, table_ny, context);
          for (unsigned int k = 0; k < grid.structures.size(); ++k)
            table.push_back({grid.structures[k],
                             values[k * n_fields + f_E],
                             values[k * n_fields + f_nu]});
        }

      auto misfit = [&](const double E, const double nu) {
        return std::pow(E / E_star - 1, 2) + std::pow(nu - target_nu, 2);
      };
      const ComplianceMisfit compliance(E_star, target_nu);
      // The optimized J: the moduli misfit or the compliance misfit.
      auto objective = [&](const Sample &r) {
        return compliance_objective ? compliance.value(r.C) :
                                      misfit(r.fit.E, r.fit.nu);
      };
      nlohmann::json shape_rows = nlohmann::json::array();
      std::vector<std::pair<double, unsigned int>> ranked;
      for (unsigned int k = 0; k < table.size(); ++k)
        if (std::count(grid.families.begin(),
                       grid.families.end(),
                       table[k].structure.family) > 0 &&
            table[k].structure.limit == grid.limit)
          ranked.push_back({misfit(table[k].E, table[k].nu), k});
      AssertThrow(!ranked.empty(),
                  ExcMessage("Inverse: the table has no sample of the "
                             "families (and Limit structures setting) of the "
                             "Sweep section"));
      std::sort(ranked.begin(), ranked.end());
      ranked.resize(std::min<std::size_t>(ranked.size(), n_candidates));

      // Refinement on the Grid resolution.
      const unsigned int ny   = setup.cells_along_height;
      const unsigned int nx   = grid_nx(ny);
      const auto         cell = family_grid(MPI_COMM_SELF, setup, ny);
      // Every rank refines the same candidates (the runs are short, and the
      // optimizer's collective output stays consistent).
      auto with = [](HexagonalLaminate s, const std::vector<double> &q) {
        if (s.limit)
          s.p1 = q[0], s.theta = q[1], s.alpha = q[2] * numbers::PI / 180;
        else
          s.p1 = q[0], s.p2 = q[1], s.p4 = q[2];
        s.check();
        return s;
      };
      auto moduli = [&](const HexagonalLaminate &s) {
        const auto r = evaluate(
          *cell,
          pixel_material(s, setup.base, setup.weak, setup.gray, nx, ny),
          setup);
        return r;
      };

      nlohmann::json    candidates     = nlohmann::json::array();
      double            best_J         = std::numeric_limits<double>::max();
      double            best_objective = std::numeric_limits<double>::max();
      HexagonalLaminate best;
      Sample            best_sample;
      for (unsigned int c = 0; c < ranked.size(); ++c)
        {
          const TableSample &start = table[ranked[c].second];
          const auto        &s0    = start.structure;
          context.print(
            "inverse: candidate " + std::to_string(c + 1) + "/" +
            std::to_string(ranked.size()) + ": " + s0.family_name() +
            (s0.limit ?
               " limit p1 = " + sig(s0.p1) + ", theta = " + sig(s0.theta) +
                 ", alpha = " + sig(s0.alpha * 180 / numbers::PI) :
               " p1 = " + sig(s0.p1) + ", p2 = " + sig(s0.p2) +
                 ", p3 = " + sig(s0.p3) + ", p4 = " + sig(s0.p4)) +
            " (table: E/Eb = " + sig(start.E / setup.base.E) +
            ", nu = " + sig(start.nu) + ")");
          DesignModel model;
          if (s0.limit)
            {
              model.initial = {s0.p1, s0.theta, s0.alpha * 180 / numbers::PI};
              model.scale   = {0.1, 0.1, 10};
              model.lower   = {0.02, 0, -89};
              model.upper   = {0.98, 1, 89};
            }
          else
            {
              model.initial = {s0.p1, s0.p2, s0.p4};
              model.scale   = {0.1, 0.1, 0.1};
              model.lower   = {0.02, 0, 0.02};
              model.upper   = {0.98, 1, 1};
            }
          // E and nu are even in p2 (alpha): a mirrored structure has the
          // same isotropic moduli, so a non-chiral start is stationary in
          // chirality and an exact gradient never leaves it. Start slightly
          // chiral (p2 = 0.05, alpha = 2 degrees).
          if (s0.limit && std::abs(model.initial[2]) < 2)
            model.initial[2] = 2;
          if (!s0.limit && model.initial[1] < 0.05)
            model.initial[1] = 0.05;
          // The line search asks for J and then the gradient at the same
          // design, and the result is the last accepted one: keep the last
          // homogenization.
          std::vector<double> last_q;
          Sample              last;
          auto                sample_at = [&](const std::vector<double> &q) {
            if (q != last_q)
              {
                last   = moduli(with(s0, q));
                last_q = q;
              }
            return last;
          };
          auto J = [&](const std::vector<double> &q) {
            return objective(sample_at(q));
          };
          model.value = J;
          // Exact: the pixel tensors' derivatives through C^H's material
          // gradient at the last homogenization (sample_at's).
          // The last gradient, for the report of an accepted design.
          std::vector<double> gradient_q, gradient;
          model.gradient = [&](const std::vector<double> &q,
                               std::vector<double>       &dJ) {
            const Sample r = sample_at(q);
            const auto   g =
              evaluate_gradient(*cell, with(s0, q), setup, nx, ny, r);
            const double dJ_dE  = 2 * (r.fit.E / E_star - 1) / E_star,
                         dJ_dnu = 2 * (r.fit.nu - target_nu);
            const auto G        = compliance.derivative(r.C);
            dJ.assign(q.size(), 0);
            for (unsigned int i = 0; i < q.size(); ++i)
              dJ[i] = compliance_objective ? full_contraction(G, g.C[i]) :
                                             dJ_dE * g.E[i] + dJ_dnu * g.nu[i];
            // The optimizer's alpha is in degrees.
            if (s0.limit)
              dJ[2] *= numbers::PI / 180;
            gradient_q = q, gradient = dJ;
            return objective(r);
          };
          model.accepted = [&](const unsigned int         k,
                               const std::vector<double> &q,
                               const double               value) {
            if (!report_shape)
              return;
            std::vector<double> dJ = gradient;
            if (q != gradient_q)
              model.gradient(q, dJ);
            double norm = 0;
            for (const double x : dJ)
              norm += x * x;
            auto row = shape_derivative_row(
              with(s0, q), setup, mesh_size, mesh_degree, compliance);
            row["candidate"]               = c + 1;
            row["iteration"]               = k;
            row["J"]                       = value;
            row["parameter_gradient_norm"] = std::sqrt(norm);
            row["structure"]               = structure_json(with(s0, q));
            context.print(
              "inverse: [iteration " + std::to_string(k) +
              "] J = " + sig(value) + ", |dJ/dq| = " + sig(std::sqrt(norm), 3) +
              "; conforming mesh: E/Eb = " +
              sig(double(row["mesh_E_over_Eb"])) +
              ", nu = " + sig(double(row["mesh_nu"])) +
              ", |dJ/dX| = " + sig(double(row["shape_derivative_norm"]), 4) +
              ", " + sig(100 * double(row["corner_share"]), 3) +
              "% of |dJ/dX|^2 near corners");
            shape_rows.push_back(row);
          };
          const auto   result = optimize(model, op, context);
          const auto   s      = with(s0, result.design);
          const auto   r      = sample_at(result.design);
          const double Jc     = misfit(r.fit.E, r.fit.nu);
          const double Jo     = objective(r);
          context.print("inverse: candidate " + std::to_string(c + 1) +
                        " reaches E/Eb = " + sig(r.fit.E / setup.base.E) +
                        ", nu = " + sig(r.fit.nu) + " (" + result.stop_reason +
                        ")");
          nlohmann::json j = structure_json(s);
          j["E_over_Eb"]   = r.fit.E / setup.base.E;
          j["nu"]          = r.fit.nu;
          j["misfit"]      = Jc;
          j["objective"]   = Jo;
          j["iterations"]  = result.history.size() - 1;
          j["stop_reason"] = result.stop_reason;
          candidates.push_back(j);
          if (Jo < best_objective)
            best_objective = Jo, best_J = Jc, best = s, best_sample = r;
          if (Jc <= op.value_target)
            break;
        }
      context.print(
        "inverse: target E/Eb = " + sig(target_E) + ", nu = " + sig(target_nu) +
        "; achieved E/Eb = " + sig(best_sample.fit.E / setup.base.E) +
        ", nu = " + sig(best_sample.fit.nu) + " (misfit " +
        sig(std::sqrt(best_J), 2) + ")");
      context.summary["target"] = {{"E_over_Eb", target_E}, {"nu", target_nu}};
      context.summary["structure"]  = structure_json(best);
      context.summary["result"]     = sample_json(best_sample, setup);
      context.summary["misfit"]     = std::sqrt(best_J);
      context.summary["reached"]    = best_J <= op.value_target;
      context.summary["candidates"] = candidates;
      if (report_shape)
        context.summary["shape_derivative"] = shape_rows;
      context.summary["grid"] = {nx, ny};
    }
  } // namespace laminate
} // namespace forma
