#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>

#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/rhombic/inverse_problem.h>
#include <forma/rhombic/material_map.h>

#include "modes.h"

#include <string>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    MaterialMap
    read_map(ParameterHandler &prm, const std::string &prm_directory)
    {
      prm.enter_subsection("Map");
      const std::string file = prm.get("Map file");
      prm.leave_subsection();
      return MaterialMap::read(path_relative_to(prm_directory, file));
    }



    void
    query_mode(ParameterHandler  &prm,
               const std::string &prm_directory,
               const Setup       &setup,
               RunContext        &context)
    {
      prm.enter_subsection("Query");
      const double E     = prm.get_double("Young's modulus");
      const double nu    = prm.get_double("Poisson's ratio");
      const double angle = prm.get_double("Angle");
      prm.leave_subsection();
      const MaterialMap map = read_map(prm, prm_directory);

      bool             inside = false;
      RhombicStructure s      = map.query(E, nu, angle, setup.base.nu, inside);
      // The evaluation cost of the map (the splines and the clamp).
      {
        Timer        timer;
        bool         dummy;
        unsigned int n = 0;
        for (; n < 1000; ++n)
          map.query(E, nu, angle, setup.base.nu, dummy);
        context.log("query: " + sig(1e6 * timer.wall_time() / n, 3) +
                    " microseconds per evaluation");
      }
      std::string p;
      for (const double v : s.p)
        p += (p.empty() ? "" : ", ") + sig(v, 4);
      context.print("query: E/E_b = " + sig(E) + ", nu = " + sig(nu) +
                    ", alpha = " + sig(angle) + " degrees -> p = " + p);
      if (!inside)
        {
          std::string          nearest = "the map covers nothing at this angle";
          const CoverageRegion region  = map.coverage(angle, setup.base.nu);
          context.summary["nearest_covered_point"] = nullptr;
          if (!region.empty())
            {
              const auto q = region.closest_point({{E, nu}});
              nearest =
                "the nearest covered point is (E/E_b, nu) = (" + sig(q[0], 3) +
                ", " + sig(q[1], 3) + ")" +
                (region.logarithmic() ? ", nearest in (log E, nu)" : "");
              context.summary["nearest_covered_point"] = q;
            }
          context.print("query: the point lies outside the map's coverage "
                        "D(alpha) (" +
                        nearest + "); the structure is an extrapolation");
        }
      const CellModel model(s, setup, context.communicator());
      const Sample   &r  = model.sample();
      const double    dE = r.fit.E / setup.base.E / E - 1, dnu = r.fit.nu - nu;
      context.print(
        "query: the structure gives E/E_b = " + sig(r.fit.E / setup.base.E) +
        " (" + sig(100 * dE, 2) + "%), nu = " + sig(r.fit.nu) + " (" +
        sig(dnu, 2) + "), a1 = " + sig(r.anisotropy.a1, 2) +
        ", a2 = " + sig(r.anisotropy.a2, 2));
      nlohmann::json &S = context.summary;
      S["query"] = {{"E_over_Eb", E}, {"nu", nu}, {"angle_degrees", angle}};
      S["inside_coverage"]  = inside;
      S["E_relative_error"] = dE;
      S["nu_error"]         = dnu;
      write_cell_results(context, s, model, setup);
    }
  } // namespace rhombic
} // namespace forma
