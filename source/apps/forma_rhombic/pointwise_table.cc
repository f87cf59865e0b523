#include "pointwise_table.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <forma/base/application.h>
#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/optimization/optimizer.h>
#include <forma/rhombic/inverse_problem.h>

#include "modes.h"
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    namespace
    {
      const std::string format = "forma-rhombic pointwise table 1";
    }



    const PointwiseTable::Entry &
    PointwiseTable::nearest(const double E, const double nu) const
    {
      AssertThrow(!entries.empty(),
                  ExcMessage("the pointwise table has no entries"));
      double E_lo = 1e300, E_hi = -1e300, nu_lo = 1e300, nu_hi = -1e300;
      for (const Entry &e : entries)
        {
          E_lo  = std::min(E_lo, e.E);
          E_hi  = std::max(E_hi, e.E);
          nu_lo = std::min(nu_lo, e.nu);
          nu_hi = std::max(nu_hi, e.nu);
        }
      const double sE       = std::max(E_hi - E_lo, 1e-12),
                   sn       = std::max(nu_hi - nu_lo, 1e-12);
      const Entry *best     = &entries[0];
      double       distance = 1e300;
      for (const Entry &e : entries)
        {
          const double d =
            std::pow((e.E - E) / sE, 2) + std::pow((e.nu - nu) / sn, 2);
          if (d < distance)
            {
              distance = d;
              best     = &e;
            }
        }
      return *best;
    }



    PointwiseTable
    PointwiseTable::read(const std::string &file)
    {
      std::ifstream in(file);
      AssertThrow(in,
                  ExcMessage("cannot read the pointwise table '" + file + "'"));
      PointwiseTable table;
      try
        {
          const auto j = nlohmann::json::parse(in);
          AssertThrow(j.at("format") == format, ExcMessage("not a " + format));
          for (const auto &e : j.at("entries"))
            {
              if (!e.at("reached").get<bool>())
                continue;
              Entry entry;
              entry.target_E    = e.at("target_E").get<double>();
              entry.target_nu   = e.at("target_nu").get<double>();
              entry.E           = e.at("E").get<double>();
              entry.nu          = e.at("nu").get<double>();
              entry.misfit      = e.at("misfit").get<double>();
              entry.structure.p = e.at("p").get<std::array<double, 8>>();
              entry.structure.alpha =
                e.at("angle_degrees").get<double>() * M_PI / 180;
              entry.structure.blending = e.at("blending").get<double>();
              entry.structure.check();
              table.entries.push_back(entry);
            }
          table.base_nu = j.at("base").at("nu").get<double>();
        }
      catch (const std::exception &e)
        {
          AssertThrow(false,
                      ExcMessage("the pointwise table '" + file +
                                 "' is malformed: " + error_message(e)));
        }
      AssertThrow(!table.entries.empty(),
                  ExcMessage("the pointwise table '" + file +
                             "' has no entry that reached its target"));
      return table;
    }



    void
    pointwise_table_mode(ParameterHandler &prm,
                         const Setup      &setup,
                         RunContext       &context)
    {
      const RhombicStructure start = read_structure(prm, setup);
      InverseProblem         problem =
        InverseProblem::read(prm, setup, start, MPI_COMM_SELF);
      OptimizationParameters op =
        inverse_optimization_parameters(prm, problem.tolerance);
      op.checkpoint = false; // many independent solves: nothing to resume
      AssertThrow(problem.target_structure[0] == 0,
                  ExcMessage("pointwise table: the targets are isotropic "
                             "(Pointwise table section); set Inverse/Target "
                             "= isotropic."));
      prm.enter_subsection("Pointwise table");
      const auto Es  = parse_values(prm.get("Young's moduli"),
                                   "Pointwise table/Young's moduli");
      const auto nus = parse_values(prm.get("Poisson's ratios"),
                                    "Pointwise table/Poisson's ratios");
      prm.leave_subsection();
      check_target_grid(Es, nus, "Pointwise table");

      // Targets round robin over the ranks, each solved alone; the rows
      // are summed over the ranks.
      constexpr unsigned int width = 7 + RhombicStructure::n_parameters;
      const unsigned int     n     = Es.size() * nus.size();
      const unsigned int     rank =
        Utilities::MPI::this_mpi_process(context.communicator());
      const unsigned int size =
        Utilities::MPI::n_mpi_processes(context.communicator());
      context.print("pointwise table: " + std::to_string(n) + " targets on a " +
                    sig(start.alpha * 180 / M_PI) + " degree cell, " +
                    std::to_string(problem.free.size()) + " free parameters");
      context.log("pointwise table: " + std::to_string(size) + " processes");
      std::vector<double> rows(width * n, 0.);
      context.quiet = true; // the solvers' iterations: log only
      for (unsigned int k = rank; k < n; k += size)
        {
          problem.target_E  = Es[k / nus.size()];
          problem.target_nu = nus[k % nus.size()];
          problem.target =
            IsotropicModuli::from_young_poisson(problem.target_E * setup.base.E,
                                                problem.target_nu)
              .tensor();
          double *row = rows.data() + width * k;
          row[0]      = problem.target_E;
          row[1]      = problem.target_nu;
          // A target that fails stays out of the table; this rank must
          // still reach the sum below.
          InverseSolution s;
          try
            {
              s = problem.solve(start, setup, MPI_COMM_SELF, op, context);
            }
          catch (const std::exception &e)
            {
              row[4] = -1; // failed
              context.log("pointwise table: the target E/E_b = " + sig(row[0]) +
                          ", nu = " + sig(row[1]) +
                          " failed: " + error_message(e));
              continue;
            }
          row[2] = s.sample.fit.E / setup.base.E;
          row[3] = s.sample.fit.nu;
          row[4] = s.misfit;
          row[5] = s.reached;
          row[6] = s.iterations;
          std::copy(s.structure.p.begin(), s.structure.p.end(), row + 7);
        }
      context.quiet = false;
      Utilities::MPI::sum(rows, context.communicator(), rows);

      nlohmann::json entries = nlohmann::json::array();
      unsigned int   reached = 0;
      for (unsigned int k = 0; k < n; ++k)
        {
          const double *row = rows.data() + width * k;
          reached += row[5] > 0.5;
          entries.push_back({{"target_E", row[0]},
                             {"target_nu", row[1]},
                             {"E", row[2]},
                             {"nu", row[3]},
                             {"misfit", row[4]},
                             {"reached", row[5] > 0.5},
                             {"iterations", row[6]},
                             {"p", std::vector<double>(row + 7, row + width)},
                             {"angle_degrees", start.alpha * 180 / M_PI},
                             {"blending", start.blending}});
          context.print("  E/E_b = " + sig(row[0], 3) +
                        ", nu = " + sig(row[1], 3) + ": " +
                        (row[4] < 0   ? std::string("FAILED (see the log)") :
                         row[5] > 0.5 ? "reached, p5 = " + sig(row[7 + 4], 2) :
                                        std::string("NOT reached")));
        }
      context.print("pointwise table: " + std::to_string(reached) + " of " +
                    std::to_string(n) + " targets reached (|C - C*|/|C*| <= " +
                    sig(problem.tolerance) + ")");
      const nlohmann::json table = {
        {"format", format},
        {"base", {{"E", setup.base.E}, {"nu", setup.base.nu}}},
        {"start", structure_json(start)},
        {"tolerance", problem.tolerance},
        {"entries", entries}};
      context.summary["pointwise_table"] = table;
      if (context.is_root())
        {
          std::ofstream out(context.path("pointwise_table.json"));
          out << table.dump(1) << std::endl;
        }
    }
  } // namespace rhombic
} // namespace forma
