#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/grid/tria.h>

#include <forma/adjoint/design.h>
#include <forma/base/application.h>
#include <forma/base/parameter_override.h>
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

#include "fine_scale_check.h"
#include "modes.h"
#include "pointwise_table.h"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <tuple>
#include <utility>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;
    using namespace two_scale;



    TwoScaleSettings
    TwoScaleSettings::parse(ParameterHandler  &prm,
                            const std::string &prm_directory)
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
      for (const auto &b : Utilities::split_string_list(prm.get("Baselines")))
        s.baselines.insert(b);
      s.table_file = resolved(prm.get("Pointwise table"));
      s.merge      = prm.get_bool("Merge joints");
      s.refinement = prm.get_integer("Fine-scale refinement");
      prm.leave_subsection();
      return s;
    }



    namespace
    {
      constexpr double degrees = 180 / M_PI;

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
