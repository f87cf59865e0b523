#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/grid/grid_out.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_out.h>

#include <forma/adjoint/design.h>
#include <forma/base/application.h>
#include <forma/base/outline.h>
#include <forma/base/parameter_override.h>
#include <forma/base/plot.h>
#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/elasticity/jobs.h>
#include <forma/elasticity/load_cases.h>
#include <forma/elasticity/parameters.h>
#include <forma/elasticity/simulator.h>
#include <forma/ipc/ipc_parameters.h>
#include <forma/mesh/cut_grid_mesh.h>
#include <forma/mesh/level_set_mesh.h>
#include <forma/mesh/polygon_domain.h>
#include <forma/rhombic/material_map.h>
#include <forma/rhombic/tiling.h>

#include "modes.h"
#include "pointwise_table.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <tuple>
#include <utility>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    namespace
    {
      constexpr double degrees = 180 / M_PI;

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


      /// Run f on the root of comm only; an error there is thrown on every
      /// rank (collective, and a barrier: the root is done when it returns).
      void
      on_root(const MPI_Comm comm, const std::function<void()> &f)
      {
        std::string error;
        if (Utilities::MPI::this_mpi_process(comm) == 0)
          try
            {
              f();
            }
          catch (const std::exception &e)
            {
              error = error_message(e);
            }
        error = Utilities::MPI::broadcast(comm, error);
        AssertThrow(error.empty(), ExcMessage(error));
      }

      /// A mesh (material and boundary ids) for the simulator to read back.
      void
      write_msh(const Triangulation<2> &tria,
                const std::string      &file,
                const MPI_Comm          comm)
      {
        on_root(comm, [&]() {
          std::ofstream msh(file);
          msh << std::setprecision(17);
          GridOut out;
          out.set_flags(GridOutFlags::Msh(/*write_faces=*/true));
          out.write_msh(tria, msh);
          AssertThrow(msh, ExcMessage("cannot write '" + file + "'"));
        });
      }


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
      scale_boundary_records(const std::string &records,
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

      /// The macro problem's parameters: a forma-transient-ipc file.
      ElasticityParameters
      read_macro_problem(const std::string &file,
                         const std::string &settings,
                         ParameterHandler  &macro)
      {
        macro.declare_entry("Dimension", "2", Patterns::Integer(2, 3));
        macro.declare_entry("Output directory", "", Patterns::Anything());
        macro.declare_entry("Mode", "", Patterns::Anything());
        ElasticityParameters::declare(macro);
        ipc::IpcParameters::declare(macro);
        declare_elasticity_job_parameters(macro);
        AssertThrow(std::filesystem::exists(file),
                    ExcMessage("Two-scale/Macro problem: the file '" + file +
                               "' does not exist."));
        try
          {
            macro.parse_input(file, "", false, true);
          }
        catch (const std::exception &e)
          {
            AssertThrow(false,
                        ExcMessage("Two-scale/Macro problem '" + file +
                                   "': " + error_message(e)));
          }
        for (const auto &assignment :
             Utilities::split_string_list(settings, '|'))
          try
            {
              set_entry(macro, assignment);
            }
          catch (const std::exception &e)
            {
              AssertThrow(false,
                          ExcMessage("Two-scale/Macro settings: " +
                                     error_message(e)));
            }
        ElasticityParameters p;
        p.parse(macro,
                std::filesystem::path(file).parent_path().string(),
                false,
                true);
        return p;
      }

      using Region = CoverageRegion;

      /**
       * The (E, nu) pairs of one design block kept inside the map's
       * coverage ('cell material' on the rhombic mesh; 'material', one body
       * per square, on the cut grid): the map's grid box as bounds, the
       * polygons D(alpha) as a soft penalty. `regions_of` gives each slot's
       * polygon from the simulator's cell centers.
       */
      struct CoverageConstraint
      {
        std::string           block;
        double                E_b;
        double                weight;
        std::array<double, 4> box; // E/E_b and nu: lo, hi, lo, hi
        std::function<std::vector<const Region *>(
          const std::vector<Point<2>> &)>
          regions_of;

        unsigned int                offset = 0; // of the block
        std::vector<const Region *> regions;    // per slot, after setup

        DesignConstraint
        constraint()
        {
          DesignConstraint c;
          c.setup = [this](const DesignLayout          &layout,
                           const std::vector<Point<2>> &centers,
                           std::vector<double>         &lower,
                           std::vector<double>         &upper) {
            const DesignBlock *b = layout.find(block);
            AssertThrow(b != nullptr, ExcInternalError());
            offset  = b->offset;
            regions = regions_of(centers);
            AssertThrow(2 * regions.size() == b->size, ExcInternalError());
            for (unsigned int g = 0; g < regions.size(); ++g)
              {
                const unsigned int i = offset + 2 * g;
                lower[i]             = std::max(lower[i], E_b * box[0]);
                upper[i]             = std::min(upper[i], E_b * box[1]);
                lower[i + 1]         = std::max(lower[i + 1], box[2]);
                upper[i + 1]         = std::min(upper[i + 1], box[3]);
              }
          };
          c.penalty = [this](const std::vector<double> &q,
                             std::vector<double>       &dP) {
            // Violation scale in the regions' coordinates: 0.01 in nu, and
            // in E/E_b or 1% of E on a log axis.
            constexpr double tau = 0.01;
            const double     w   = weight / regions.size();
            double           P   = 0;
            for (unsigned int g = 0; g < regions.size(); ++g)
              {
                const unsigned int    i    = offset + 2 * g;
                std::array<double, 2> grad = {{0, 0}};
                P +=
                  w * regions[g]->penalty({{q[i] / E_b, q[i + 1]}}, tau, grad);
                dP[i] += w * grad[0] / E_b;
                dP[i + 1] += w * grad[1];
              }
            return P;
          };
          return c;
        }
      };

      /// What projecting the materials into the coverage moved: how many
      /// slots, the largest violation, and the slot moved furthest, from
      /// where to where.
      struct Projection
      {
        unsigned int          outside    = 0;
        double                worst      = 0;
        double                moved      = 0;
        unsigned int          moved_slot = 0;
        std::array<double, 2> from{}, to{};

        /// "N <what> projected into the coverage", and the furthest one
        /// (`name` gives its number as the user knows it).
        std::string
        describe(const std::string                              &what,
                 const std::function<std::string(unsigned int)> &name) const
        {
          std::string text = std::to_string(outside) + " " + what +
                             " projected into the coverage (largest "
                             "distance " +
                             sig(worst, 2) + ")";
          if (outside > 0)
            text += "; moved furthest: " + name(moved_slot) +
                    ", (E/E_b, nu) = (" + sig(from[0], 3) + ", " +
                    sig(from[1], 3) + ") moved to the nearest covered point (" +
                    sig(to[0], 3) + ", " + sig(to[1], 3) + ")";
          return text;
        }
      };

      /**
       * The block's materials (E/E_b, nu) per slot: optimized for the
       * macro problem in `context`, or `constant` ('E/E_b, nu') in every
       * slot; then projected into their regions (the closest point,
       * `projection` says what moved). q becomes the design with the
       * projected materials, what the structures are built for.
       */
      std::vector<std::array<double, 2>>
      design_materials(CoverageConstraint         &coverage,
                       const ElasticityParameters &parameters,
                       ParameterHandler           &macro,
                       RunContext                 &context,
                       const std::string          &constant,
                       std::vector<double>        &q,
                       Projection                 &projection)
      {
        DesignConstraint constraint = coverage.constraint();
        if (constant.empty())
          q = run_elasticity_job(
            "optimize", parameters, macro, context, &constraint);
        else
          {
            const auto m = Utilities::split_string_list(constant);
            AssertThrow(m.size() == 2,
                        ExcMessage("Two-scale/Constant material: give "
                                   "'E/E_b, nu', e.g. '0.05, 0.3'."));
            LoadCases<2> probe(parameters, context.communicator());
            probe.prepare(nullptr);
            q = probe.design();
            std::vector<double> lower(q.size()), upper(q.size());
            constraint.setup(probe.design_layout(),
                             probe[0].cell_centers(),
                             lower,
                             upper);
            for (unsigned int g = 0; g < coverage.regions.size(); ++g)
              {
                q[coverage.offset + 2 * g] =
                  coverage.E_b * Utilities::string_to_double(m[0]);
                q[coverage.offset + 2 * g + 1] =
                  Utilities::string_to_double(m[1]);
              }
          }
        std::vector<std::array<double, 2>> materials;
        projection = Projection();
        for (unsigned int g = 0; g < coverage.regions.size(); ++g)
          {
            const unsigned int          i = coverage.offset + 2 * g;
            const std::array<double, 2> m = {{q[i] / coverage.E_b, q[i + 1]}};
            const Region               &region = *coverage.regions[g];
            const double                v = std::max(0., region.violation(m));
            materials.push_back(region.closest_point(m));
            // Distances in the region's coordinates (log E on a log axis).
            const auto   to    = region.coordinates(materials.back());
            const auto   from  = region.coordinates(m);
            const double moved = std::hypot(to[0] - from[0], to[1] - from[1]);
            projection.outside += v > 1e-6;
            projection.worst = std::max(projection.worst, v);
            if (v > 1e-6 && moved > projection.moved)
              {
                projection.moved      = moved;
                projection.moved_slot = g;
                projection.from       = m;
                projection.to         = materials.back();
              }
            q[i]     = coverage.E_b * materials.back()[0];
            q[i + 1] = materials.back()[1];
          }
        return materials;
      }

      /// The Two-scale section, read once; file names relative to the
      /// parameter file's directory.
      struct TwoScaleSettings
      {
        std::string           macro_file, macro_settings, constant_material;
        std::string           table_file;
        double                coverage_weight = 0;
        bool                  fine_check = true, check_moduli = false;
        bool                  fine_simulation = true, merge = true;
        double                fine_size = 0, fine_boundary_size = 0;
        int                   compared_boundary = -1;
        unsigned int          refinement        = 0;
        std::set<std::string> baselines;

        static TwoScaleSettings
        parse(ParameterHandler &prm, const std::string &prm_directory)
        {
          const auto resolved = [&](const std::string &file) {
            return file.empty() || file[0] == '/' ? file :
                                                    prm_directory + "/" + file;
          };
          TwoScaleSettings s;
          prm.enter_subsection("Two-scale");
          s.macro_file         = resolved(prm.get("Macro problem"));
          s.macro_settings     = prm.get("Macro settings");
          s.coverage_weight    = prm.get_double("Coverage weight");
          s.fine_check         = prm.get_bool("Fine-scale check");
          s.fine_size          = prm.get_double("Fine element size");
          s.fine_boundary_size = prm.get_double("Fine boundary element size");
          s.compared_boundary  = prm.get_integer("Compared boundary");
          s.constant_material  = prm.get("Constant material");
          s.check_moduli       = prm.get_bool("Check cell moduli");
          s.fine_simulation    = prm.get_bool("Fine-scale simulation");
          for (const auto &b :
               Utilities::split_string_list(prm.get("Baselines")))
            s.baselines.insert(b);
          s.table_file = resolved(prm.get("Pointwise table"));
          s.merge      = prm.get_bool("Merge joints");
          s.refinement = prm.get_integer("Fine-scale refinement");
          prm.leave_subsection();
          return s;
        }
      };

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

      /// A tiling's fine-scale mesh: boundary ids from the outline and the
      /// compared boundary's vertices.
      struct FineMesh
      {
        Triangulation<2>                 tria;
        LevelSetMeshInfo                 info;
        std::map<unsigned int, Point<2>> compared_points;
        std::string                      file;
      };

      /**
       * The fine-scale check of one tiling (ch. 4.8): the tiled geometry
       * meshed and simulated in the base material with the macro problem's
       * supports and loads, against the homogenized solution on the
       * compared boundary.
       */
      class FineScaleCheck
      {
      public:
        FineScaleCheck(const TwoScaleSettings                  &settings,
                       const PolygonDomain                     &domain,
                       const ElasticityParameters              &parameters,
                       const Setup                             &setup,
                       RunContext                              &context,
                       const double                             h,
                       const double                             h_tile,
                       std::function<void(const std::string &)> lap)
          : settings(settings)
          , domain(domain)
          , parameters(parameters)
          , setup(setup)
          , context(context)
          , h(h)
          , h_tile(h_tile)
          , lap(std::move(lap))
        {}

        void
        operator()(const std::function<double(const Point<2> &)> &object,
                   const Point<2>                                &object_lo,
                   const Point<2>                                &object_hi,
                   const std::string                             &name,
                   LoadCases<2> &homogenized) const
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

      private:
        /// The geometry meshed, written as .msh and its outline as SVG and
        /// DXF (for fabrication).
        void
        mesh(const std::function<double(const Point<2> &)> &object,
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
          fine.largest_piece_only = true;
          const Tensor<1, 2> pad = Tensor<1, 2>({0.25 * h_tile, 0.25 * h_tile});
          const Point<2>     lower = object_lo - pad, upper = object_hi + pad;
          fine.grid = std::min<unsigned int>(
            8192,
            static_cast<unsigned int>(
              std::ceil(std::max(upper[0] - lower[0], upper[1] - lower[1]) /
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
          on_root(context.communicator(), [&]() {
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

        /// The base material in the fine mesh under the macro problem's
        /// supports and first load case (loads scaled to the fine
        /// boundary's lengths); its VTU in fine_scale_<name>/.
        std::unique_ptr<ElasticitySimulator<2>>
        simulate(const FineMesh    &fine,
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
            std::make_unique<ElasticitySimulator<2>>(fp,
                                                     context.communicator());
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
          on_root(context.communicator(), [&]() {
            write_deformation_png(context.path("fine_scale_" + name + ".png"),
                                  fine_cells,
                                  homogenized_cells);
          });
          return simulator;
        }

        /// Fine against homogenized displacements on the compared boundary.
        void
        compare(const FineMesh               &fine,
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
          context.print(
            "fine scale, " + name + ": on boundary " +
            std::to_string(settings.compared_boundary) +
            " |u_fine - u_homogenized| / max |u_homogenized|: mean " +
            sig(mean / largest, 2) + ", max " + sig(worst_error / largest, 2));
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

        const TwoScaleSettings     &settings;
        const PolygonDomain        &domain;
        const ElasticityParameters &parameters;
        const Setup                &setup;
        RunContext                 &context;
        const double                h, h_tile;
        // By value: it may be a lambda converted at the call (it captures
        // the caller's timer by reference).
        const std::function<void(const std::string &)> lap;
      };

      /// The design's pictures (materials per cell, the tiled geometry)
      /// and design.vtu (per cell: E, nu, alpha, p1..p8), on the root.
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
        on_root(context.communicator(), [&]() {
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

      /// The macro problem solved for the design q.
      std::unique_ptr<LoadCases<2>>
      solved(const ElasticityParameters &parameters,
             const std::vector<double>  &q,
             const MPI_Comm              comm)
      {
        auto cases = std::make_unique<LoadCases<2>>(parameters, comm);
        cases->prepare(nullptr);
        if (!parameters.objective.terms.empty())
          cases->set_objective(parameters.objective);
        cases->set_design(q);
        cases->solve_design();
        return cases;
      }



      /// Tilings, optionally of cells subdivided n_sub x n_sub (Fig. 4.21).
      struct Tiler
      {
        unsigned int n_sub;
        bool         merge;

        TiledObject
        operator()(const std::vector<Quad>             &quads,
                   const std::vector<RhombicStructure> &tiles) const
        {
          if (n_sub == 1)
            return TiledObject(quads, tiles, {}, merge);
          // Children keep their parent's orientation.
          std::vector<Quad> oriented;
          for (const Quad &q : quads)
            oriented.push_back(acute_first(q));
          std::vector<unsigned int> parent;
          const std::vector<Quad> children = subdivide(oriented, n_sub, parent);
          std::vector<RhombicStructure> inherited;
          for (const unsigned int c : parent)
            inherited.push_back(tiles[c]);
          return TiledObject(children, inherited, {}, merge, false);
        }
      };

      /**
       * The cut grid baseline (Fig. 4.20): a regular grid of squares with
       * the rhombic mesh's mean edge, cut by the outline; its materials
       * optimized for the same macro problem, each square given its square
       * structure, the geometry cropped by the outline and checked at the
       * fine scale against its own homogenized solution.
       */
      void
      cut_grid_baseline(const Triangulation<2, 2>   &tria,
                        const PolygonDomain         &domain,
                        const ElasticityParameters  &parameters,
                        const MaterialMap           &map,
                        const Setup                 &setup,
                        const TwoScaleSettings      &settings,
                        const std::array<double, 4> &box,
                        ParameterHandler            &macro,
                        RunContext                  &context,
                        const std::function<void(const std::string &)> &lap,
                        const Tiler                                    &tile,
                        const FineScaleCheck &fine_scale)
      {
        const double E_b     = setup.base.E;
        double       edge    = 0;
        unsigned int n_edges = 0;
        for (const auto &face : tria.active_face_iterators())
          {
            edge += face->measure();
            ++n_edges;
          }
        edge /= n_edges;
        Triangulation<2>      cut_tria;
        std::vector<Point<2>> corners;
        cut_grid_mesh(domain,
                      domain.lo,
                      edge,
                      0.5 * edge,
                      cut_tria,
                      corners,
                      context.communicator());
        const std::string cut_file = context.path("cut_grid_mesh.msh");
        write_msh(cut_tria, cut_file, context.communicator());
        ElasticityParameters cut = parameters;
        cut.mesh.file            = cut_file;
        cut.mesh.file_as_given   = "cut_grid_mesh.msh";
        cut.design.blocks        = {"material"};
        cut.design.bodies        = "";
        const Region square      = map.coverage(90, setup.base.nu);
        AssertThrow(!square.empty(),
                    ExcMessage("Two-scale/Baselines: the cut grid's "
                               "squares need the map's coverage at 90 "
                               "degrees, which it does not have."));
        CoverageConstraint cut_coverage{"material",
                                        E_b,
                                        settings.coverage_weight,
                                        box,
                                        [&](const std::vector<Point<2>> &) {
                                          return std::vector<const Region *>(
                                            corners.size(), &square);
                                        },
                                        0,
                                        {}};
        context.print("cut grid: " + std::to_string(corners.size()) +
                      " squares of side " + sig(edge, 3) +
                      " (the rhombic mesh's mean edge)" +
                      (settings.constant_material.empty() ?
                         "; materials optimized on them" :
                         ""));
        std::vector<double>                q_cut;
        Projection                         cut_projection;
        std::vector<std::array<double, 2>> cut_materials;
        nlohmann::json                     cut_summary;
        {
          // Its optimization history, VTU and convergence plot apart.
          RunContext cut_context(context.communicator(),
                                 context.path("cut_grid"));
          cut_context.quiet = true;
          // Optimization/Resume means the main design's checkpoint.
          macro.enter_subsection("Optimization");
          const bool resume = macro.get_bool("Resume");
          macro.set("Resume", false);
          macro.leave_subsection();
          cut_materials = design_materials(cut_coverage,
                                           cut,
                                           macro,
                                           cut_context,
                                           settings.constant_material,
                                           q_cut,
                                           cut_projection);
          macro.enter_subsection("Optimization");
          macro.set("Resume", resume);
          macro.leave_subsection();
          cut_summary = cut_context.summary;
          cut_context.commit();
        }
        context.log(
          "cut grid: " + std::to_string(cut_tria.n_active_cells()) +
          " triangles; " +
          cut_projection.describe("squares", [](const unsigned int k) {
            return "square " + std::to_string(k);
          }));
        lap("cut grid materials");
        std::vector<Quad>             quads;
        std::vector<RhombicStructure> tiles;
        for (unsigned int k = 0; k < corners.size(); ++k)
          {
            const Point<2> &o = corners[k];
            quads.push_back({{o,
                              o + Tensor<1, 2>({edge, 0.}),
                              o + Tensor<1, 2>({0., edge}),
                              o + Tensor<1, 2>({edge, edge})}});
            bool inside = false;
            tiles.push_back(map.query(cut_materials[k][0],
                                      cut_materials[k][1],
                                      90,
                                      setup.base.nu,
                                      inside));
          }
        const TiledObject grid    = tile(quads, tiles);
        const auto        cropped = [&](const Point<2> &x) {
          return std::max(grid(x), domain.signed_distance(x));
        };
        fine_scale(cropped,
                   domain.lo,
                   domain.hi,
                   "cut_grid",
                   *solved(cut, q_cut, context.communicator()));
        context.summary["cut_grid"] = {
          {"squares", corners.size()},
          {"side", edge},
          {"triangles", cut_tria.n_active_cells()},
          {"projected_squares", cut_projection.outside},
          {"largest_coverage_violation", cut_projection.worst}};
        if (cut_summary.count("final_objective"))
          context.summary["cut_grid"]["final_objective"] =
            cut_summary["final_objective"];
        on_root(context.communicator(), [&]() {
          write_level_set_picture(context.path("cut_grid_geometry.png"),
                                  cropped,
                                  domain.lo,
                                  domain.hi);
        });
      }
    } // namespace



    void
    two_scale_design_mode(ParameterHandler  &prm,
                          const std::string &prm_directory,
                          const Setup       &setup,
                          RunContext        &context)
    {
      const TwoScaleSettings settings =
        TwoScaleSettings::parse(prm, prm_directory);
      // The baselines' table first: a bad file must not cost a design.
      PointwiseTable table;
      if (settings.baselines.count("pointwise table"))
        {
          AssertThrow(!settings.table_file.empty(),
                      ExcMessage("Two-scale/Baselines: 'pointwise table' "
                                 "needs Two-scale/Pointwise table (a "
                                 "pointwise_table.json of Mode = pointwise "
                                 "table)."));
          table = PointwiseTable::read(settings.table_file);
          AssertThrow(std::abs(table.base_nu - setup.base.nu) < 1e-12,
                      ExcMessage("Two-scale/Pointwise table: the table was "
                                 "built for a base Poisson's ratio of " +
                                 sig(table.base_nu) + ", this run's base has " +
                                 sig(setup.base.nu) + "."));
        }
      const MaterialMap map           = read_map(prm, prm_directory);
      const auto [angle_lo, angle_hi] = map.covered_angles();

      // Wall seconds per stage (log and summary only: not deterministic).
      nlohmann::json seconds;
      Timer          timer;
      const auto     lap = [&](const std::string &stage) {
        seconds[stage] = timer.wall_time();
        context.log("seconds, " + stage + ": " + sig(timer.wall_time(), 3));
        timer.restart();
      };

      // 1. The rhombic quad mesh (ch. 4.7).
      Triangulation<2, 2> tria;
      const QuadMeshShape shape =
        make_rhombic_mesh(prm, prm_directory, context, tria);
      const std::string   mesh_file = context.path("rhombic_mesh.msh");
      const PolygonDomain domain    = PolygonDomain::boundary_of(tria);
      MPI_Barrier(context.communicator()); // the root wrote it

      // Each quad's angle, clamped to the map's range, and its region D.
      const unsigned int          n_cells = tria.n_active_cells();
      std::vector<double>         alpha(n_cells);
      std::vector<CoverageRegion> region(n_cells);
      std::vector<Point<2>>       centers;
      unsigned int                clamped = 0;
      for (const auto &cell : tria.active_cell_iterators())
        {
          const unsigned int c = cell->active_cell_index();
          const double       a = shape.alpha[c] * degrees;
          alpha[c]             = std::clamp(a, angle_lo, angle_hi);
          clamped += (alpha[c] != a);
          region[c] = map.coverage(alpha[c], setup.base.nu);
          AssertThrow(!region[c].empty(),
                      ExcMessage("the map has no coverage at " + sig(alpha[c]) +
                                 " degrees (cell " + std::to_string(c) + ")."));
          centers.push_back(cell->center());
        }
      context.print("map: angles " + sig(angle_lo) + "-" + sig(angle_hi) +
                    " degrees; " + std::to_string(clamped) +
                    " quads sharper than the map's range use its smallest "
                    "angle");

      lap("rhombic mesh");

      // 2. Per-cell materials for the macro problem (ch. 4.8).
      ParameterHandler     macro;
      ElasticityParameters parameters =
        read_macro_problem(settings.macro_file, settings.macro_settings, macro);
      AssertThrow(parameters.dim == 2 && parameters.plane_stress,
                  ExcMessage("Two-scale/Macro problem: the homogenized "
                             "moduli are 2D; set Dimension = 2 and "
                             "Material/Plane = stress."));
      AssertThrow(parameters.design.blocks ==
                      std::vector<std::string>{"cell material"} &&
                    parameters.design.young_poisson,
                  ExcMessage("Two-scale/Macro problem: the design must be "
                             "'cell material' alone, in Young's modulus and "
                             "Poisson's ratio."));
      parameters.mesh.source               = "file";
      parameters.mesh.file                 = mesh_file;
      parameters.mesh.file_as_given        = "rhombic_mesh.msh";
      parameters.mesh.initial_refinement   = 0;
      parameters.mesh.convert_to_simplices = false; // cells are the quads

      // The simulator numbers cells its own way: match them by center.
      std::vector<unsigned int>   quad_of;
      const double                E_b = setup.base.E;
      const std::array<double, 4> box = {
        {map.E.front(),
         map.E.back(),
         map.nu.front() + setup.base.nu * map.E.front(),
         map.nu.back() + setup.base.nu * map.E.back()}};
      CoverageConstraint coverage{
        "cell material",
        E_b,
        settings.coverage_weight,
        box,
        [&](const std::vector<Point<2>> &simulator_centers) {
          AssertThrow(simulator_centers.size() == n_cells,
                      ExcMessage("Two-scale/Macro problem: its mesh must be "
                                 "the rhombic quad mesh, cell for cell (no "
                                 "refinement or adaptivity)."));
          quad_of.assign(n_cells, 0);
          std::vector<bool>           matched(n_cells, false);
          std::vector<const Region *> regions;
          for (unsigned int g = 0; g < n_cells; ++g)
            {
              double best = 1e300;
              for (unsigned int c = 0; c < n_cells; ++c)
                if (centers[c].distance_square(simulator_centers[g]) < best)
                  {
                    best = centers[c].distance_square(simulator_centers[g]);
                    quad_of[g] = c;
                  }
              AssertThrow(best < 1e-10 * tria.begin_active()->measure() &&
                            !matched[quad_of[g]],
                          ExcMessage("Two-scale: a cell of the macro problem "
                                     "matches no quad of the rhombic mesh."));
              matched[quad_of[g]] = true;
              regions.push_back(&region[quad_of[g]]);
            }
          return regions;
        },
        0,
        {}};
      if (settings.constant_material.empty())
        context.print("material optimization on the rhombic mesh (" +
                      std::to_string(n_cells) + " cells)");
      std::vector<double> q;
      Projection          projection;
      const auto          materials = design_materials(coverage,
                                              parameters,
                                              macro,
                                              context,
                                              settings.constant_material,
                                              q,
                                              projection);
      if (!settings.constant_material.empty())
        {
          const auto m =
            Utilities::split_string_list(settings.constant_material);
          context.print("constant material E/E_b = " + m[0] + ", nu = " + m[1] +
                        " in all " + std::to_string(n_cells) + " cells");
        }

      lap("materials");

      // 3. Each cell's structure from the map (ch. 4.6), inside D(alpha).
      std::vector<RhombicStructure> structures(n_cells);
      std::vector<double>           E(n_cells), nu(n_cells);
      for (unsigned int g = 0; g < n_cells; ++g)
        {
          const unsigned int c = quad_of[g];
          E[c]                 = materials[g][0];
          nu[c]                = materials[g][1];
          bool inside          = false;
          structures[c] =
            map.query(E[c], nu[c], alpha[c], setup.base.nu, inside);
        }
      context.print("materials: E/E_b " +
                    sig(*std::min_element(E.begin(), E.end()), 3) + "-" +
                    sig(*std::max_element(E.begin(), E.end()), 3) + ", nu " +
                    sig(*std::min_element(nu.begin(), nu.end()), 3) + "-" +
                    sig(*std::max_element(nu.begin(), nu.end()), 3) + "; " +
                    projection.describe("cells", [&](const unsigned int g) {
                      return "cell " + std::to_string(quad_of[g]) + " (" +
                             sig(alpha[quad_of[g]], 3) + " degrees)";
                    }));

      lap("map");

      if (settings.check_moduli)
        {
          check_cell_moduli(structures, E, nu, setup, context);
          lap("cell moduli");
        }

      // 4. Fine-scale check (ch. 4.8): the tiled geometry meshed and
      // simulated in the base material with the same supports and loads,
      // against the homogenized solution (per-cell materials) on the
      // compared boundary.
      // The family against the baseline of ch. 4.8 (Fig. 4.22): structures
      // made for squares (the map at 90 degrees) mapped onto the quads.
      double h = 0; // the quads' mean size
      for (const auto &cell : tria.active_cell_iterators())
        h += std::sqrt(cell->measure()) / n_cells;
      // A baseline that cannot be built, meshed or solved is reported, not
      // fatal: the design is the family's.
      const auto baseline = [&](const std::string           &name,
                                const std::function<void()> &run) {
        try
          {
            run();
          }
        catch (const std::exception &e)
          {
            const std::string message = error_message(e);
            context.print("baseline " + name + " failed: " + message);
            context.summary["fine_scale"][name] = {{"error", message}};
          }
      };

      // Tilings, optionally of subdivided cells (Fig. 4.21).
      const unsigned int   n_sub  = 1u << settings.refinement;
      const double         h_tile = h / n_sub;
      const Tiler          tile{n_sub, settings.merge};
      const FineScaleCheck fine_scale(
        settings, domain, parameters, setup, context, h, h_tile, lap);
      const TiledObject tiled = tile(quads_of(tria), structures);
      const auto tiled_phi = [&tiled](const Point<2> &x) { return tiled(x); };
      if (settings.fine_check)
        {
          // The family, then the baselines of ch. 4.8, each against its own
          // homogenized solution.
          const auto homogenized =
            solved(parameters, q, context.communicator());
          fine_scale(tiled_phi, tiled.lo, tiled.hi, "family", *homogenized);
          if (settings.baselines.count("remapped square"))
            baseline("remapped_square", [&]() {
              // Fig. 4.22: structures made for squares on the same quads.
              std::vector<RhombicStructure> squares(n_cells);
              for (unsigned int c = 0; c < n_cells; ++c)
                {
                  bool inside = false;
                  squares[c] =
                    map.query(E[c], nu[c], 90, setup.base.nu, inside);
                }
              const TiledObject remapped = tile(quads_of(tria), squares);
              fine_scale([&remapped](const Point<2> &x) { return remapped(x); },
                         remapped.lo,
                         remapped.hi,
                         "remapped_square",
                         *homogenized);
            });
          if (settings.baselines.count("pointwise table"))
            baseline("pointwise_table", [&]() {
              // Fig. 4.23: the same quads and materials, each quad given the
              // table's structure nearest to its material, mapped onto it.
              std::vector<RhombicStructure> looked_up(n_cells);
              double                        dE = 0, dnu = 0;
              for (unsigned int c = 0; c < n_cells; ++c)
                {
                  const auto &e = table.nearest(E[c], nu[c]);
                  looked_up[c]  = e.structure;
                  dE += std::abs(e.E / E[c] - 1) / n_cells;
                  dnu += std::abs(e.nu - nu[c]) / n_cells;
                }
              context.print(
                "pointwise table: " + std::to_string(table.entries.size()) +
                " structures; nearest entry |E/E* - 1| mean " + sig(dE, 2) +
                ", |nu - nu*| mean " + sig(dnu, 2));
              const TiledObject pointwise = tile(quads_of(tria), looked_up);
              fine_scale([&pointwise](
                           const Point<2> &x) { return pointwise(x); },
                         pointwise.lo,
                         pointwise.hi,
                         "pointwise_table",
                         *homogenized);
              context.print("pointwise table: joint radii p5 of neighbours "
                            "differ by up to " +
                            sig(pointwise.largest_joint_mismatch, 2) +
                            (settings.merge ? " (merged)" : "") +
                            "; the family's by up to " +
                            sig(tiled.largest_joint_mismatch, 2));
              context.summary["pointwise_table"] = {
                {"largest_joint_mismatch", pointwise.largest_joint_mismatch},
                {"family_largest_joint_mismatch", tiled.largest_joint_mismatch},
                {"entries", table.entries.size()},
                {"mean_lookup_E_error", dE},
                {"mean_lookup_nu_error", dnu}};
            });
        }
      if (settings.fine_check && settings.baselines.count("cut grid"))
        baseline("cut_grid", [&]() {
          cut_grid_baseline(tria,
                            domain,
                            parameters,
                            map,
                            setup,
                            settings,
                            box,
                            macro,
                            context,
                            lap,
                            tile,
                            fine_scale);
        });
      context.summary["seconds"] = seconds;

      nlohmann::json cells = nlohmann::json::array();
      for (unsigned int c = 0; c < n_cells; ++c)
        {
          std::vector<double> p(structures[c].p.begin(), structures[c].p.end());
          cells.push_back({{"center", {centers[c][0], centers[c][1]}},
                           {"alpha", alpha[c]},
                           {"E_relative", E[c]},
                           {"nu", nu[c]},
                           {"parameters", p}});
        }
      context.summary["cells"]     = cells;
      context.summary["two_scale"] = {{"cells", n_cells},
                                      {"clamped_angles", clamped},
                                      {"projected_cells", projection.outside},
                                      {"largest_coverage_violation",
                                       projection.worst}};
      write_design_outputs(
        tria, E, nu, alpha, structures, map, box, tiled, context);
    }
  } // namespace rhombic
} // namespace forma
