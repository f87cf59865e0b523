#include <deal.II/base/parameter_handler.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_out.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_out.h>

#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/mesh/mesh.h>
#include <forma/mesh/quad_mesh.h>
#include <forma/rhombic/quad_mesh_optimization.h>

#include "modes.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    namespace
    {
      constexpr double degrees = 180 / M_PI;

      nlohmann::json
      shape_json(const QuadMeshShape &s)
      {
        return {{"min_alpha_degrees", s.min_alpha * degrees},
                {"mean_alpha_degrees", s.mean_alpha * degrees},
                {"min_interior_angle_degrees", s.min_interior_angle * degrees},
                {"mean_rhombic_error", s.mean_error},
                {"max_rhombic_error", s.max_error}};
      }

      // Round-off of exact rhombi prints as 0 (machine-independent output).
      std::string
      small(const double x)
      {
        return x < 1e-9 ? std::string("0") : sig(x, 3);
      }

      std::string
      shape_line(const QuadMeshShape &s)
      {
        return "alpha min " + sig(s.min_alpha * degrees, 4) + ", mean " +
               sig(s.mean_alpha * degrees, 4) + " degrees; smallest corner " +
               sig(s.min_interior_angle * degrees, 4) +
               " degrees; rhombic error mean " + small(s.mean_error) +
               ", max " + small(s.max_error);
      }

      void
      write_shape_vtu(const std::string         &file_name,
                      const Triangulation<2, 2> &tria,
                      const QuadMeshShape       &s)
      {
        Vector<double> alpha(tria.n_active_cells()),
          error(tria.n_active_cells()), corner(tria.n_active_cells());
        for (unsigned int c = 0; c < alpha.size(); ++c)
          {
            alpha[c]  = s.alpha[c] * degrees;
            error[c]  = s.rhombic_error[c];
            corner[c] = s.smallest_angle[c] * degrees;
          }
        DataOut<2> out;
        out.attach_triangulation(tria);
        out.add_data_vector(alpha, "alpha", DataOut<2>::type_cell_data);
        out.add_data_vector(error, "rhombic_error", DataOut<2>::type_cell_data);
        out.add_data_vector(corner,
                            "smallest_angle",
                            DataOut<2>::type_cell_data);
        out.build_patches();
        std::ofstream f(file_name);
        out.write_vtu(f);
      }
    } // namespace



    void
    read_quad_mesh(ParameterHandler    &prm,
                   const std::string   &prm_directory,
                   Triangulation<2, 2> &tria)
    {
      prm.enter_subsection("Quad mesh");
      const std::string  file       = prm.get("File");
      const double       size       = prm.get_double("Element size");
      const unsigned int refinement = prm.get_integer("Refinement");
      prm.leave_subsection();
      AssertThrow(!file.empty(),
                  ExcMessage("Quad mesh/File: name a .msh or .geo file."));
      const std::string path =
        std::filesystem::path(file).is_absolute() ?
          file :
          (std::filesystem::path(prm_directory) / file).string();
      AssertThrow(std::filesystem::exists(path),
                  ExcMessage("Quad mesh/File: cannot open '" + file +
                             "' (looked relative to the parameter file's "
                             "directory)."));
      Triangulation<2, 2> coarse;
      if (std::filesystem::path(file).extension() == ".geo")
        gmsh_quad_mesh(path, size, coarse);
      else
        {
          MeshParameters m;
          m.source        = "file";
          m.file          = path;
          m.file_as_given = file;
          create_coarse_mesh<2>(m, coarse);
        }
      AssertThrow(coarse.all_reference_cells_are_hyper_cube(),
                  ExcMessage("Quad mesh/File '" + file +
                             "': the mesh has triangles; the cells of the "
                             "microstructure must be quadrilaterals."));
      coarse.refine_global(refinement);
      tria.clear();
      GridGenerator::flatten_triangulation(coarse, tria);
    }



    void
    rhombic_mesh_mode(ParameterHandler  &prm,
                      const std::string &prm_directory,
                      RunContext        &context)
    {
      Triangulation<2, 2> tria;
      make_rhombic_mesh(prm, prm_directory, context, tria);
    }



    QuadMeshShape
    make_rhombic_mesh(ParameterHandler    &prm,
                      const std::string   &prm_directory,
                      RunContext          &context,
                      Triangulation<2, 2> &tria)
    {
      read_quad_mesh(prm, prm_directory, tria);
      QuadMeshOptimizationParameters parameters;
      prm.enter_subsection("Quad mesh");
      parameters.parse(prm);
      prm.leave_subsection();

      context.print("quad mesh: " + std::to_string(tria.n_active_cells()) +
                    " quads, " + std::to_string(tria.n_used_vertices()) +
                    " vertices");
      Triangulation<2, 2> input;
      input.copy_triangulation(tria);
      const QuadMeshOptimizationResult r =
        optimize_rhombic_mesh(tria, parameters);
      context.print("input:     " + shape_line(r.before));
      double         last_exponent = -1, last_weight = 0;
      nlohmann::json history = nlohmann::json::array();
      for (const auto &h : r.history)
        {
          history.push_back({{"exponent", h.exponent},
                             {"floor_weight", h.floor_weight},
                             {"iteration", h.iteration},
                             {"distortion", h.energy},
                             {"boundary_deviation", h.deviation},
                             {"max_move", h.max_move}});
          if (h.exponent != last_exponent || h.floor_weight != last_weight)
            context.log("s = " + sig(h.exponent) +
                        (h.floor_weight > 0 ?
                           ", angle floor weight " + sig(h.floor_weight, 3) :
                           std::string()) +
                        ":");
          last_exponent = h.exponent;
          last_weight   = h.floor_weight;
          context.log("  iteration " + std::to_string(h.iteration) +
                      ": distortion " + sig(h.energy, 6) + ", max move " +
                      sig(h.max_move, 3) + " h, line search halvings " +
                      std::to_string(h.line_search_halvings));
        }
      // One line per exponent and per round of the angle floor.
      unsigned int round = 0;
      for (unsigned int k = 0; k < r.history.size(); ++k)
        if (k + 1 == r.history.size() ||
            r.history[k + 1].exponent != r.history[k].exponent ||
            r.history[k + 1].floor_weight != r.history[k].floor_weight)
          {
            const std::string stage =
              r.history[k].floor_weight > 0 ?
                "angle floor round " + std::to_string(++round) :
                "s = " + sig(r.history[k].exponent);
            context.log(stage + ": " +
                        std::to_string(r.history[k].iteration + 1) +
                        " iterations");
            context.print(stage + ": distortion " +
                          sig(r.history[k].energy, 3));
          }
      context.print("optimized: " + shape_line(r.after));
      if (parameters.angle_floor > 0)
        {
          const auto low =
            std::min_element(r.after.alpha.begin(), r.after.alpha.end());
          const bool met = r.angle_floor_met;
          context.print(
            "angle floor " + sig(parameters.angle_floor * degrees, 4) +
            " degrees: " +
            (met ?
               std::string("met") :
               "NOT met: quad " + std::to_string(low - r.after.alpha.begin()) +
                 " stays at " + sig(*low * degrees, 4) +
                 " degrees (its vertices' valence or the outline "
                 "leave no room; refine the quad mesh or lower the "
                 "floor)"));
          context.summary["angle_floor_degrees"] =
            parameters.angle_floor * degrees;
          context.summary["angle_floor_met"] = met;
        }
      context.print("boundary: largest distance from the input boundary " +
                    (r.boundary_deviation < 1e-9 ?
                       std::string("below 1e-9") :
                       sig(r.boundary_deviation, 2)) +
                    " mean edge lengths");

      context.summary["quads"]              = tria.n_active_cells();
      context.summary["mean_edge"]          = r.mean_edge;
      context.summary["input"]              = shape_json(r.before);
      context.summary["optimized"]          = shape_json(r.after);
      context.summary["boundary_deviation"] = r.boundary_deviation;
      context.summary["history"]            = history;
      if (context.is_root())
        {
          std::ofstream msh(context.path("rhombic_mesh.msh"));
          msh << std::setprecision(17); // the macro problem reads it
          GridOut out;
          out.set_flags(GridOutFlags::Msh(/*write_faces=*/true));
          out.write_msh(tria, msh);
          write_shape_vtu(context.path("quad_mesh.vtu"), input, r.before);
          write_shape_vtu(context.path("rhombic_mesh.vtu"), tria, r.after);
          std::vector<double> alpha;
          for (const double a : r.after.alpha)
            alpha.push_back(a * degrees);
          for (const std::string extension : {".png", ".svg"})
            write_cell_field(context.path("rhombic_mesh" + extension),
                             tria,
                             alpha,
                             {{parameters.min_angle * degrees, 90}},
                             "rhombus angle α (°)");
        }
      return r.after;
    }
  } // namespace rhombic
} // namespace forma
