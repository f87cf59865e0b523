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
#include <memory>
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


      /// The Inverse and Conforming mesh sections, read once.
      struct InverseSettings
      {
        double                 target_E = 0, target_nu = 0;
        std::string            table_file; ///< resolved; empty: none
        unsigned int           table_ny = 0, n_candidates = 0;
        OptimizationParameters op;
        bool                   compliance_objective = false;
        bool                   report_shape         = false;
        double                 mesh_size            = 0;
        unsigned int           mesh_degree          = 0;
      };



      InverseSettings
      read_inverse_settings(ParameterHandler &prm, const std::string &directory)
      {
        InverseSettings s;
        prm.enter_subsection("Inverse");
        s.target_E             = prm.get_double("Target Young's modulus");
        s.target_nu            = prm.get_double("Target Poisson's ratio");
        s.table_file           = prm.get("Table file");
        s.table_ny             = prm.get_integer("Table cells along height");
        s.n_candidates         = prm.get_integer("Candidates");
        s.op.max_iterations    = prm.get_integer("Max iterations");
        const double tolerance = prm.get_double("Tolerance");
        s.compliance_objective = prm.get("Objective") == "compliance";
        s.report_shape         = prm.get_bool("Report shape derivative");
        prm.leave_subsection();
        AssertThrow(!s.report_shape || s.compliance_objective,
                    ExcMessage("Inverse/Report shape derivative needs "
                               "Inverse/Objective = compliance (thesis Table "
                               "5.1's objective)."));
        prm.enter_subsection("Conforming mesh");
        s.mesh_size   = prm.get_double("Element size");
        s.mesh_degree = prm.get_integer("Degree");
        prm.leave_subsection();
        if (!s.table_file.empty() && s.table_file[0] != '/')
          s.table_file = directory + "/" + s.table_file;
        s.op.value_target       = s.compliance_objective ?
                                    -std::numeric_limits<double>::infinity() :
                                    tolerance * tolerance;
        s.op.relative_decrease  = 1e-6;
        s.op.decrease_window    = 3;
        s.op.gradient_tolerance = 1e-8;
        s.op.print_iterations   = false;
        return s;
      }



      /// No structure reaches a target beyond the Hashin-Shtrikman bounds.
      void
      check_target(const InverseSettings &s, const Setup &setup)
      {
        AssertThrow(s.target_E > 0,
                    ExcMessage("Inverse/Target Young's modulus: must be "
                               "positive (no structure has E = 0)"));
        const auto hs = hashin_shtrikman(setup.base, setup.weak, 1);
        AssertThrow(
          s.target_E * setup.base.E <= hs.max_young_modulus(s.target_nu) &&
            s.target_nu > -1 && s.target_nu < 1,
          ExcMessage("Inverse: the target (E/Eb, nu) = (" + sig(s.target_E) +
                     ", " + sig(s.target_nu) +
                     ") lies outside the Hashin-Shtrikman bounds "
                     "(E/Eb <= " +
                     sig(hs.max_young_modulus(s.target_nu) / setup.base.E) +
                     " at this nu): no structure reaches it"));
      }



      /// The table the candidates come from: the given file, or the Sweep
      /// grid homogenized on a coarse grid.
      std::vector<TableSample>
      starting_table(const InverseSettings &s,
                     const SweepGrid       &grid,
                     const Setup           &setup,
                     RunContext            &context)
      {
        std::vector<TableSample> table;
        if (!s.table_file.empty())
          {
            table = read_sample_table(s.table_file);
            context.print("inverse: " + std::to_string(table.size()) +
                          " samples from the table file");
            return table;
          }
        const auto values =
          homogenize_all(grid.structures, setup, s.table_ny, context);
        for (unsigned int k = 0; k < grid.structures.size(); ++k)
          table.push_back({grid.structures[k],
                           values[k * n_fields + f_E],
                           values[k * n_fields + f_nu]});
        return table;
      }



      /// The structure with the design variables q: p1, p2, p4, or p1,
      /// theta and alpha in degrees.
      HexagonalLaminate
      with(HexagonalLaminate s, const std::vector<double> &q)
      {
        if (s.limit)
          s.p1 = q[0], s.theta = q[1], s.alpha = q[2] * numbers::PI / 180;
        else
          s.p1 = q[0], s.p2 = q[1], s.p4 = q[2];
        s.check();
        return s;
      }



      /// The design variables of with() at s0, their bounds and scales.
      DesignModel
      design_variables(const HexagonalLaminate &s0)
      {
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
        return model;
      }



      /// The moduli misfit J = (E/E* - 1)^2 + (nu - nu*)^2 (E absolute).
      double
      moduli_misfit(const InverseSettings &s,
                    const Setup           &setup,
                    const double           E,
                    const double           nu)
      {
        return std::pow(E / (s.target_E * setup.base.E) - 1, 2) +
               std::pow(nu - s.target_nu, 2);
      }



      /// What a candidate's refinement reaches.
      struct Refined
      {
        HexagonalLaminate structure;
        Sample            sample;
        /// The moduli misfit and the optimized objective.
        double         misfit = 0, objective = 0;
        nlohmann::json summary;
      };



      /**
       * The refinement of the candidates on the Grid resolution: J (the
       * moduli misfit or the compliance misfit) and its exact gradient
       * (the pixel tensors' derivatives through C^H's material gradient).
       * Every rank refines the same candidates (the runs are short, and
       * the optimizer's collective output stays consistent).
       */
      class Refinement
      {
      public:
        Refinement(const InverseSettings &s,
                   const Setup           &setup,
                   RunContext            &context)
          : s(s)
          , setup(setup)
          , context(context)
          , E_star(s.target_E * setup.base.E)
          , compliance(E_star, s.target_nu)
          , ny(setup.cells_along_height)
          , nx(grid_nx(ny))
          , cell(family_grid(MPI_COMM_SELF, setup, ny))
        {}

        double
        misfit(const double E, const double nu) const
        {
          return moduli_misfit(s, setup, E, nu);
        }

        /// The optimized J.
        double
        objective(const Sample &r) const
        {
          return s.compliance_objective ? compliance.value(r.C) :
                                          misfit(r.fit.E, r.fit.nu);
        }

        /// Candidate `c` (from 1) refined from s0; Table 5.1's rows (Report
        /// shape derivative) go to shape_rows.
        Refined
        run(const HexagonalLaminate &s0,
            const unsigned int       c,
            nlohmann::json          &shape_rows);

        unsigned int
        grid_width() const
        {
          return nx;
        }

      private:
        Sample
        moduli(const HexagonalLaminate &structure) const
        {
          return evaluate(
            *cell,
            pixel_material(
              structure, setup.base, setup.weak, setup.gray, nx, ny),
            setup);
        }

        /// dJ/dq at the homogenization r of with(s0, q); returns J.
        double
        gradient(const HexagonalLaminate   &s0,
                 const std::vector<double> &q,
                 const Sample              &r,
                 std::vector<double>       &dJ) const;

        /// Table 5.1's row for an accepted iterate.
        nlohmann::json
        shape_row(const HexagonalLaminate   &structure,
                  const unsigned int         k,
                  const double               value,
                  const std::vector<double> &dJ) const;

        const InverseSettings                     &s;
        const Setup                               &setup;
        RunContext                                &context;
        const double                               E_star;
        const ComplianceMisfit                     compliance;
        const unsigned int                         ny, nx;
        std::unique_ptr<PeriodicHomogenization<2>> cell;
      };



      double
      Refinement::gradient(const HexagonalLaminate   &s0,
                           const std::vector<double> &q,
                           const Sample              &r,
                           std::vector<double>       &dJ) const
      {
        const auto g = evaluate_gradient(*cell, with(s0, q), setup, nx, ny, r);
        const double dJ_dE  = 2 * (r.fit.E / E_star - 1) / E_star,
                     dJ_dnu = 2 * (r.fit.nu - s.target_nu);
        const auto G        = compliance.derivative(r.C);
        dJ.assign(q.size(), 0);
        for (unsigned int i = 0; i < q.size(); ++i)
          dJ[i] = s.compliance_objective ? full_contraction(G, g.C[i]) :
                                           dJ_dE * g.E[i] + dJ_dnu * g.nu[i];
        // The optimizer's alpha is in degrees.
        if (s0.limit)
          dJ[2] *= numbers::PI / 180;
        return objective(r);
      }



      nlohmann::json
      Refinement::shape_row(const HexagonalLaminate   &structure,
                            const unsigned int         k,
                            const double               value,
                            const std::vector<double> &dJ) const
      {
        double norm = 0;
        for (const double x : dJ)
          norm += x * x;
        norm     = std::sqrt(norm);
        auto row = shape_derivative_row(
          structure, setup, s.mesh_size, s.mesh_degree, compliance);
        row["iteration"]               = k;
        row["J"]                       = value;
        row["parameter_gradient_norm"] = norm;
        row["structure"]               = structure_json(structure);
        context.print(
          "inverse: [iteration " + std::to_string(k) + "] J = " + sig(value) +
          ", |dJ/dq| = " + sig(norm, 3) +
          "; conforming mesh: E/Eb = " + sig(double(row["mesh_E_over_Eb"])) +
          ", nu = " + sig(double(row["mesh_nu"])) +
          ", |dJ/dX| = " + sig(double(row["shape_derivative_norm"]), 4) + ", " +
          sig(100 * double(row["corner_share"]), 3) +
          "% of |dJ/dX|^2 near corners");
        return row;
      }



      Refined
      Refinement::run(const HexagonalLaminate &s0,
                      const unsigned int       c,
                      nlohmann::json          &shape_rows)
      {
        DesignModel model = design_variables(s0);
        // The line search asks for J and then the gradient at the same
        // design, and the result is the last accepted one: keep the last
        // homogenization.
        std::vector<double> last_q;
        Sample              last;
        const auto          sample_at = [&](const std::vector<double> &q) {
          if (q != last_q)
            {
              last   = moduli(with(s0, q));
              last_q = q;
            }
          return last;
        };
        model.value = [&](const std::vector<double> &q) {
          return objective(sample_at(q));
        };
        // The last gradient, for the report of an accepted design.
        std::vector<double> gradient_q, last_gradient;
        model.gradient = [&](const std::vector<double> &q,
                             std::vector<double>       &dJ) {
          const double J = gradient(s0, q, sample_at(q), dJ);
          gradient_q = q, last_gradient = dJ;
          return J;
        };
        model.accepted = [&](const unsigned int         k,
                             const std::vector<double> &q,
                             const double               value) {
          if (!s.report_shape)
            return;
          std::vector<double> dJ = last_gradient;
          if (q != gradient_q)
            model.gradient(q, dJ);
          auto row         = shape_row(with(s0, q), k, value, dJ);
          row["candidate"] = c;
          shape_rows.push_back(row);
        };
        const auto result = optimize(model, s.op, context);
        Refined    out;
        out.structure = with(s0, result.design);
        out.sample    = sample_at(result.design);
        out.misfit    = misfit(out.sample.fit.E, out.sample.fit.nu);
        out.objective = objective(out.sample);
        context.print(
          "inverse: candidate " + std::to_string(c) +
          " reaches E/Eb = " + sig(out.sample.fit.E / setup.base.E) +
          ", nu = " + sig(out.sample.fit.nu) + " (" + result.stop_reason + ")");
        out.summary                = structure_json(out.structure);
        out.summary["E_over_Eb"]   = out.sample.fit.E / setup.base.E;
        out.summary["nu"]          = out.sample.fit.nu;
        out.summary["misfit"]      = out.misfit;
        out.summary["objective"]   = out.objective;
        out.summary["iterations"]  = result.history.size() - 1;
        out.summary["stop_reason"] = result.stop_reason;
        return out;
      }



      /// "hexagon p1 = ..., p2 = ..." as the progress lines name a start.
      std::string
      describe(const TableSample &start, const Setup &setup)
      {
        const auto &s = start.structure;
        return s.family_name() +
               (s.limit ?
                  " limit p1 = " + sig(s.p1) + ", theta = " + sig(s.theta) +
                    ", alpha = " + sig(s.alpha * 180 / numbers::PI) :
                  " p1 = " + sig(s.p1) + ", p2 = " + sig(s.p2) +
                    ", p3 = " + sig(s.p3) + ", p4 = " + sig(s.p4)) +
               " (table: E/Eb = " + sig(start.E / setup.base.E) +
               ", nu = " + sig(start.nu) + ")";
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
      const InverseSettings s = read_inverse_settings(prm, prm_directory);
      check_target(s, setup);
      const SweepGrid                grid = read_sweep_grid(prm);
      const std::vector<TableSample> table =
        starting_table(s, grid, setup, context);

      // The table's samples of the Sweep section's families, nearest first.
      std::vector<std::pair<double, unsigned int>> ranked;
      for (unsigned int k = 0; k < table.size(); ++k)
        if (std::count(grid.families.begin(),
                       grid.families.end(),
                       table[k].structure.family) > 0 &&
            table[k].structure.limit == grid.limit)
          ranked.push_back(
            {moduli_misfit(s, setup, table[k].E, table[k].nu), k});
      AssertThrow(!ranked.empty(),
                  ExcMessage("Inverse: the table has no sample of the "
                             "families (and Limit structures setting) of the "
                             "Sweep section"));
      std::sort(ranked.begin(), ranked.end());
      ranked.resize(std::min<std::size_t>(ranked.size(), s.n_candidates));

      Refinement     refinement(s, setup, context);
      nlohmann::json shape_rows = nlohmann::json::array();
      nlohmann::json candidates = nlohmann::json::array();
      Refined        best;
      best.objective = std::numeric_limits<double>::max();
      best.misfit    = std::numeric_limits<double>::max();
      for (unsigned int c = 0; c < ranked.size(); ++c)
        {
          const TableSample &start = table[ranked[c].second];
          context.print("inverse: candidate " + std::to_string(c + 1) + "/" +
                        std::to_string(ranked.size()) + ": " +
                        describe(start, setup));
          Refined r = refinement.run(start.structure, c + 1, shape_rows);
          candidates.push_back(r.summary);
          const bool reached = r.misfit <= s.op.value_target;
          if (r.objective < best.objective)
            best = std::move(r);
          if (reached)
            break;
        }
      context.print("inverse: target E/Eb = " + sig(s.target_E) +
                    ", nu = " + sig(s.target_nu) + "; achieved E/Eb = " +
                    sig(best.sample.fit.E / setup.base.E) +
                    ", nu = " + sig(best.sample.fit.nu) + " (misfit " +
                    sig(std::sqrt(best.misfit), 2) + ")");
      context.summary["target"]     = {{"E_over_Eb", s.target_E},
                                       {"nu", s.target_nu}};
      context.summary["structure"]  = structure_json(best.structure);
      context.summary["result"]     = sample_json(best.sample, setup);
      context.summary["misfit"]     = std::sqrt(best.misfit);
      context.summary["reached"]    = best.misfit <= s.op.value_target;
      context.summary["candidates"] = candidates;
      if (s.report_shape)
        context.summary["shape_derivative"] = shape_rows;
      context.summary["grid"] = {refinement.grid_width(),
                                 setup.cells_along_height};
    }
  } // namespace laminate
} // namespace forma
