#include "fine_scale_check.h"

#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_out.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_out.h>

#include <forma/base/application.h>
#include <forma/base/on_root.h>
#include <forma/base/outline.h>
#include <forma/base/plot.h>
#include <forma/base/records.h>
#include <forma/base/run_context.h>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <optional>

namespace forma
{
  namespace rhombic
  {
    namespace two_scale
    {
      using namespace dealii;

      namespace
      {
        using DeformedCells =
          std::vector<std::vector<std::pair<Point<2>, Tensor<1, 2>>>>;

        /// The deformed fine-scale object (gray) with the deformed quads of
        /// the homogenized solution (red) over it.
        void
        write_deformation_png(const std::string   &file_name,
                              const DeformedCells &fine,
                              const DeformedCells &homogenized)
        {
          const auto deformed = [](const DeformedCells &cells) {
            std::vector<std::vector<std::array<double, 2>>> polygons;
            for (const auto &c : cells)
              {
                polygons.emplace_back();
                for (const auto &[x, u] : c)
                  polygons.back().push_back({{x[0] + u[0], x[1] + u[1]}});
              }
            return polygons;
          };
          write_overlay(file_name, deformed(fine), deformed(homogenized));
        }

        /**
         * Boundary load records ('<id> : <expressions>' separated by ';')
         * with every expression of boundary `id` multiplied by factor[id]:
         * the fine-scale object touches a loaded side only where its
         * material does, so its traction is raised by (side length) /
         * (length of material on it) to carry the same force.
         */
        std::string
        scale_boundary_records(
          const std::string                          &records,
          const std::map<types::boundary_id, double> &factor)
        {
          std::string result;
          for (const std::string &record :
               Utilities::split_string_list(records, ';'))
            {
              const auto colon = record.find(':');
              AssertThrow(colon != std::string::npos,
                          ExcMessage("boundary load record '" + record +
                                     "' has no ':'"));
              const auto id =
                static_cast<types::boundary_id>(Utilities::string_to_int(
                  Utilities::trim(record.substr(0, colon))));
              const double k = factor.count(id) ? factor.at(id) : 1.;
              // Expressions separated by the commas outside parentheses.
              std::vector<std::string> expressions(1);
              int                      depth = 0;
              for (const char ch : record.substr(colon + 1))
                {
                  depth += (ch == '(') - (ch == ')');
                  if (ch == ',' && depth == 0)
                    expressions.emplace_back();
                  else
                    expressions.back() += ch;
                }
              std::string scaled =
                Utilities::trim(record.substr(0, colon)) + " :";
              for (unsigned int i = 0; i < expressions.size(); ++i)
                scaled += std::string(i ? "," : "") + " (" +
                          Utilities::trim(expressions[i]) + ")*" +
                          Utilities::to_string(k, 17);
              result += (result.empty() ? "" : " ; ") + scaled;
            }
          return result;
        }
      } // namespace



      /// The material {phi < 0} of a level set on points, over [lo, hi].
      void
      write_level_set_picture(
        const std::string                             &file,
        const std::function<double(const Point<2> &)> &phi,
        const Point<2>                                &lo,
        const Point<2>                                &hi)
      {
        forma::write_level_set(file,
                               [&phi](const double x, const double y) {
                                 return phi(Point<2>(x, y));
                               },
                               {{lo[0], lo[1]}},
                               {{hi[0], hi[1]}});
      }


      /// A mesh (material and boundary ids) for the simulator to read back.
      void
      write_msh(const Triangulation<2> &tria,
                const std::string      &file,
                const MPI_Comm          comm)
      {
        on_root_or_throw(comm, [&]() {
          std::ofstream msh(file);
          msh << std::setprecision(17);
          GridOut out;
          out.set_flags(GridOutFlags::Msh(/*write_faces=*/true));
          out.write_msh(tria, msh);
          AssertThrow(msh, ExcMessage("cannot write '" + file + "'"));
        });
      }



      /**
       * The cells' structures homogenized: how far the map's structures are
       * from their targets (identical structures are homogenized once). A
       * structure the cell mesher cannot mesh is reported and left out:
       * this is a diagnosis, the tiling does not use the cell meshes.
       */
      void
      check_cell_moduli(const std::vector<RhombicStructure> &structures,
                        const std::vector<double>           &E,
                        const std::vector<double>           &nu,
                        const Setup                         &setup,
                        RunContext                          &context)
      {
        const unsigned int n_cells = structures.size();
        std::map<std::vector<double>, std::optional<Sample>> done;
        double       mean_E = 0, max_E = 0, mean_nu = 0, max_nu = 0, mean_a = 0;
        unsigned int n_checked = 0;
        std::string  first_failure;
        for (unsigned int c = 0; c < n_cells; ++c)
          {
            // Rounded: the same structure from round-off-different fits.
            std::vector<double> key;
            for (const double v : structures[c].p)
              key.push_back(std::round(v * 1e9));
            key.push_back(std::round(structures[c].alpha * 1e9));
            if (!done.count(key))
              try
                {
                  done[key] =
                    evaluate(structures[c], setup, context.communicator());
                }
              catch (const std::exception &e)
                {
                  done[key] = std::nullopt;
                  if (first_failure.empty())
                    first_failure = "cell " + std::to_string(c) + " (E/E_b " +
                                    sig(E[c], 3) + ", nu " + sig(nu[c], 3) +
                                    ", " +
                                    sig(structures[c].alpha * 180 / M_PI, 4) +
                                    " degrees): " + error_message(e);
                }
            if (!done.at(key))
              continue;
            const Sample &r  = *done.at(key);
            const double  eE = std::abs(r.fit.E / setup.base.E / E[c] - 1);
            const double  en = std::abs(r.fit.nu - nu[c]);
            ++n_checked;
            mean_E += eE;
            mean_nu += en;
            max_E  = std::max(max_E, eE);
            max_nu = std::max(max_nu, en);
            mean_a += std::max(r.anisotropy.a1, r.anisotropy.a2);
          }
        if (n_checked > 0)
          mean_E /= n_checked, mean_nu /= n_checked, mean_a /= n_checked;
        const unsigned int n_failed = n_cells - n_checked;
        const unsigned int n_failed_distinct =
          std::count_if(done.begin(), done.end(), [](const auto &d) {
            return !d.second.has_value();
          });
        if (n_failed > 0)
          context.print(
            "cell structures homogenized: " + std::to_string(n_failed) +
            " cells not homogenized (left out below), the first " +
            first_failure);
        context.print("cell structures homogenized (" +
                      std::to_string(done.size() - n_failed_distinct) +
                      " distinct): |E/E* - 1| mean " + sig(mean_E, 3) +
                      ", max " + sig(max_E, 3) + "; |nu - nu*| mean " +
                      sig(mean_nu, 3) + ", max " + sig(max_nu, 3) +
                      "; anisotropy max(a1, a2) mean " + sig(mean_a, 3));
        context.summary["cell_moduli"] = {{"distinct_structures",
                                           done.size() - n_failed_distinct},
                                          {"cells_not_homogenized", n_failed},
                                          {"mean_relative_E_error", mean_E},
                                          {"max_relative_E_error", max_E},
                                          {"mean_nu_error", mean_nu},
                                          {"max_nu_error", max_nu},
                                          {"mean_anisotropy", mean_a}};
      }



      void
      FineScaleCheck::operator()(
        const std::function<double(const Point<2> &)> &object,
        const Point<2>                                &object_lo,
        const Point<2>                                &object_hi,
        const std::string                             &name,
        LoadCases<2>                                  &homogenized) const
      {
        FineMesh fine;
        mesh(object, object_lo, object_hi, name, fine);
        if (!settings.fine_simulation)
          {
            context.log("fine scale, " + name + ": " +
                        std::to_string(fine.tria.n_active_cells()) +
                        " triangles (not simulated)");
            return;
          }
        const auto fine_simulator = simulate(fine, name, homogenized);
        compare(fine, *fine_simulator, name, homogenized);
      }



      void
      FineScaleCheck::mesh(
        const std::function<double(const Point<2> &)> &object,
        const Point<2>                                &object_lo,
        const Point<2>                                &object_hi,
        const std::string                             &name,
        FineMesh                                      &result) const
      {
        LevelSetMeshParameters fine;
        fine.size          = settings.fine_size * h_tile;
        fine.boundary_size = settings.fine_boundary_size * h_tile;
        // Where neighbouring structures meet in a sliver thinner than
        // the boundary elements, thicken it there rather than fail.
        fine.max_thickenings = 20;
        // Slivers cut off where structures meet would float.
        fine.largest_piece_only  = true;
        const Tensor<1, 2> pad   = Tensor<1, 2>({0.25 * h_tile, 0.25 * h_tile});
        const Point<2>     lower = object_lo - pad, upper = object_hi + pad;
        fine.grid                   = std::min<unsigned int>(8192,
                                           static_cast<unsigned int>(std::ceil(
                                             std::max(upper[0] - lower[0],
                                                      upper[1] - lower[1]) /
                                             (0.02 * h_tile))));
        Triangulation<2> &fine_tria = result.tria;
        LevelSetMeshInfo &info      = result.info;
        level_set_mesh(object,
                       lower,
                       upper,
                       fine,
                       fine_tria,
                       context.communicator(),
                       &info,
                       "fine-scale geometry (" + name + ")");
        // Boundary ids from the outline; holes get an id it does not use:
        // free.
        types::boundary_id free_id = 0;
        for (const auto &loop : domain.loops)
          for (const types::boundary_id i : loop.ids)
            free_id = std::max<types::boundary_id>(free_id, i + 1);
        auto &compared_points = result.compared_points;
        for (const auto &cell : fine_tria.active_cell_iterators())
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary())
              {
                const types::boundary_id id =
                  domain.boundary_id(cell->face(f)->center(),
                                     1e-3 * h,
                                     free_id);
                cell->face(f)->set_boundary_id(id);
                // Vertices of the compared boundary, nudged into their
                // cell for the fine solution; the homogenized one is
                // evaluated just inside the outline next to them (the
                // fine mesh cuts the outline's corners).
                if (static_cast<int>(id) == settings.compared_boundary)
                  for (unsigned int v = 0; v < 2; ++v)
                    {
                      const Point<2> x = cell->face(f)->vertex(v);
                      compared_points[cell->face(f)->vertex_index(v)] =
                        x + 1e-6 * (cell->center() - x);
                    }
              }
        AssertThrow(!compared_points.empty(),
                    ExcMessage("Two-scale/Compared boundary: no part of "
                               "the fine-scale geometry lies on boundary " +
                               std::to_string(settings.compared_boundary) +
                               "."));
        result.file = context.path("fine_mesh_" + name + ".msh");
        write_msh(fine_tria, result.file, context.communicator());
        on_root_or_throw(context.communicator(), [&]() {
          // The outline for fabrication (e.g. a laser cutter).
          std::vector<std::vector<std::array<double, 2>>> outline;
          for (const auto &loop :
               PolygonDomain::boundary_of(fine_tria, false).loops)
            {
              outline.emplace_back();
              for (const Point<2> &v : loop.vertices)
                outline.back().push_back({{v[0], v[1]}});
            }
          write_polygons_svg(context.path("geometry_" + name + ".svg"),
                             outline,
                             1e-3 * h);
          write_polygons_dxf(context.path("geometry_" + name + ".dxf"),
                             outline);
        });
        lap("fine mesh, " + name);
        context.summary["fine_scale"][name] = {
          {"triangles", fine_tria.n_active_cells()},
          {"dropped_islands", info.dropped_islands},
          {"thickened_slivers", info.thickenings}};
        if (info.thickenings + info.dropped_islands > 0)
          context.print("fine scale, " + name + ": thickened " +
                        std::to_string(info.thickenings) +
                        " sliver(s) thinner than the boundary elements, "
                        "dropped " +
                        std::to_string(info.dropped_islands) +
                        " loose piece(s)");
      }



      std::unique_ptr<ElasticitySimulator<2>>
      FineScaleCheck::simulate(const FineMesh    &fine,
                               const std::string &name,
                               LoadCases<2>      &homogenized) const
      {
        const Triangulation<2> &fine_tria = fine.tria;
        const std::string      &fine_file = fine.file;
        ElasticityParameters    fp        = parameters;
        fp.mesh.file                      = fine_file;
        fp.mesh.file_as_given             = "fine_mesh_" + name + ".msh";
        fp.bodies = "* : E = " + Utilities::to_string(setup.base.E, 17) +
                    ", nu = " + Utilities::to_string(setup.base.nu, 17);
        {
          std::map<types::boundary_id, double> fine_length;
          for (const auto &cell : fine_tria.active_cell_iterators())
            for (const unsigned int f : cell->face_indices())
              if (cell->face(f)->at_boundary())
                fine_length[cell->face(f)->boundary_id()] +=
                  cell->face(f)->measure();
          std::map<types::boundary_id, double> factor;
          for (const auto &[id, l] : fine_length)
            if (domain.length(id) > 0)
              factor[id] = domain.length(id) / l;
          // The check uses the first load case (what homogenized[0] has).
          if (!fp.load_cases.empty())
            fp.traction = Utilities::split_string_list(fp.load_cases, '|')[0];
          fp.load_cases.clear();
          fp.traction = scale_boundary_records(fp.traction, factor);
          fp.pressure = scale_boundary_records(fp.pressure, factor);
        }
        fp.design.blocks.clear();
        fp.objective.terms = "";
        fp.write_vtu       = true;
        fp.points          = "";
        auto simulator =
          std::make_unique<ElasticitySimulator<2>>(fp, context.communicator());
        ElasticitySimulator<2> &fine_simulator = *simulator;
        {
          // Its VTU, PVD and summary in a subdirectory of the results.
          RunContext fine_context(context.communicator(),
                                  context.path("fine_scale_" + name));
          fine_context.quiet = true;
          fine_simulator.run(&fine_context);
          fine_context.commit();
        }
        // Collective: every rank gathers, the root draws.
        const DeformedCells fine_cells =
          fine_simulator.cell_vertex_displacements();
        const DeformedCells homogenized_cells =
          homogenized[0].cell_vertex_displacements();
        on_root_or_throw(context.communicator(), [&]() {
          write_deformation_png(context.path("fine_scale_" + name + ".png"),
                                fine_cells,
                                homogenized_cells);
        });
        return simulator;
      }



      void
      FineScaleCheck::compare(const FineMesh               &fine,
                              const ElasticitySimulator<2> &fine_simulator,
                              const std::string            &name,
                              LoadCases<2>                 &homogenized) const
      {
        const Triangulation<2> &fine_tria       = fine.tria;
        const LevelSetMeshInfo &info            = fine.info;
        const auto             &compared_points = fine.compared_points;
        double                  mean = 0, worst_error = 0, largest = 0;
        for (const auto &[v, x] : compared_points)
          {
            const Tensor<1, 2> uf = fine_simulator.point_displacement(x);
            const Tensor<1, 2> uh = homogenized[0].point_displacement(
              domain.point_inside_near(x, 1e-4 * h));
            mean += (uf - uh).norm() / compared_points.size();
            worst_error = std::max(worst_error, (uf - uh).norm());
            largest     = std::max(largest, uh.norm());
          }
        AssertThrow(largest > 0,
                    ExcMessage("Two-scale/Compared boundary " +
                               std::to_string(settings.compared_boundary) +
                               " does not move in the homogenized "
                               "solution: compare where it deforms."));
        // Mesh sizes and the third digit change with round-off in the
        // contours: the log has them, stdout two digits.
        context.log("fine scale, " + name + ": " +
                    std::to_string(fine_tria.n_active_cells()) +
                    " triangles, " + std::to_string(fine_simulator.n_dofs()) +
                    " dofs, mean error " + sig(mean / largest, 4) + ", max " +
                    sig(worst_error / largest, 4));
        context.print("fine scale, " + name + ": on boundary " +
                      std::to_string(settings.compared_boundary) +
                      " |u_fine - u_homogenized| / max |u_homogenized|: mean " +
                      sig(mean / largest, 2) + ", max " +
                      sig(worst_error / largest, 2));
        lap("fine solve, " + name);
        context.summary["fine_scale"][name] = {
          {"triangles", fine_tria.n_active_cells()},
          {"dofs", fine_simulator.n_dofs()},
          {"dropped_islands", info.dropped_islands},
          {"thickened_slivers", info.thickenings},
          {"compared_boundary", settings.compared_boundary},
          {"compared_points", compared_points.size()},
          {"max_homogenized_displacement", largest},
          {"mean_relative_error", mean / largest},
          {"max_relative_error", worst_error / largest}};
      }



      void
      write_design_outputs(const Triangulation<2, 2>           &tria,
                           const std::vector<double>           &E,
                           const std::vector<double>           &nu,
                           const std::vector<double>           &alpha,
                           const std::vector<RhombicStructure> &structures,
                           const MaterialMap                   &map,
                           const std::array<double, 4>         &box,
                           const TiledObject                   &tiled,
                           RunContext                          &context)
      {
        const unsigned int n_cells = structures.size();
        const auto tiled_phi = [&tiled](const Point<2> &x) { return tiled(x); };
        on_root_or_throw(context.communicator(), [&]() {
          // PNG previews, and SVG with real strokes for papers.
          for (const std::string extension : {".png", ".svg"})
            {
              write_cell_field(context.path("material_E" + extension),
                               tria,
                               E,
                               {{map.E.front(), map.E.back()}},
                               "E / E_b (cell materials)");
              write_cell_field(context.path("material_nu" + extension),
                               tria,
                               nu,
                               {{box[2], box[3]}},
                               "Poisson's ratio ν (cell materials)");
            }
          write_level_set_picture(context.path("geometry.png"),
                                  tiled_phi,
                                  tiled.lo,
                                  tiled.hi);
          Vector<double> vE(E.begin(), E.end()), vnu(nu.begin(), nu.end()),
            va(alpha.begin(), alpha.end());
          DataOut<2> out;
          out.attach_triangulation(tria);
          out.add_data_vector(vE, "E_relative", DataOut<2>::type_cell_data);
          out.add_data_vector(vnu, "nu", DataOut<2>::type_cell_data);
          out.add_data_vector(va, "alpha", DataOut<2>::type_cell_data);
          std::vector<Vector<double>> pv(RhombicStructure::n_parameters,
                                         Vector<double>(n_cells));
          for (unsigned int i = 0; i < RhombicStructure::n_parameters; ++i)
            {
              for (unsigned int c = 0; c < n_cells; ++c)
                pv[i][c] = structures[c].p[i];
              out.add_data_vector(pv[i],
                                  "p" + std::to_string(i + 1),
                                  DataOut<2>::type_cell_data);
            }
          out.build_patches();
          std::ofstream f(context.path("design.vtu"));
          out.write_vtu(f);
        });
      }
    } // namespace two_scale
  }   // namespace rhombic
} // namespace forma
