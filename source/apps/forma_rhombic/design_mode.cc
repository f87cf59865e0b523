#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/grid/tria.h>

#include <forma/adjoint/design.h>
#include <forma/base/application.h>
#include <forma/base/on_root.h>
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
        on_root_or_throw(context.communicator(), [&]() {
          write_level_set_picture(context.path("cut_grid_geometry.png"),
                                  cropped,
                                  domain.lo,
                                  domain.hi);
        });
      }


      /// Two-scale/Pointwise table, read first: a bad file must not cost a
      /// design (empty unless the 'pointwise table' baseline is asked for).
      PointwiseTable
      read_baseline_table(const TwoScaleSettings &settings, const Setup &setup)
      {
        PointwiseTable table;
        if (!settings.baselines.count("pointwise table"))
          return table;
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
        return table;
      }



      /// The rhombic mesh's quads as the map sees them: each quad's angle
      /// clamped to the map's range, its coverage region D and its center.
      struct MapCells
      {
        std::vector<double>         alpha;
        std::vector<CoverageRegion> region;
        std::vector<Point<2>>       centers;
        unsigned int                clamped = 0;
      };



      MapCells
      map_cells(const Triangulation<2, 2> &tria,
                const QuadMeshShape       &shape,
                const MaterialMap         &map,
                const Setup               &setup,
                const RunContext          &context)
      {
        const auto [angle_lo, angle_hi] = map.covered_angles();
        const unsigned int n_cells      = tria.n_active_cells();
        MapCells           m;
        m.alpha.resize(n_cells);
        m.region.resize(n_cells);
        for (const auto &cell : tria.active_cell_iterators())
          {
            const unsigned int c = cell->active_cell_index();
            const double       a = shape.alpha[c] * degrees;
            m.alpha[c]           = std::clamp(a, angle_lo, angle_hi);
            m.clamped += (m.alpha[c] != a);
            m.region[c] = map.coverage(m.alpha[c], setup.base.nu);
            AssertThrow(!m.region[c].empty(),
                        ExcMessage("the map has no coverage at " +
                                   sig(m.alpha[c]) + " degrees (cell " +
                                   std::to_string(c) + ")."));
            m.centers.push_back(cell->center());
          }
        context.print("map: angles " + sig(angle_lo) + "-" + sig(angle_hi) +
                      " degrees; " + std::to_string(m.clamped) +
                      " quads sharper than the map's range use its smallest "
                      "angle");
        return m;
      }



      /// Two-scale/Macro problem, on the rhombic mesh written to
      /// `mesh_file`, checked for what the two-scale design needs.
      ElasticityParameters
      macro_problem(const TwoScaleSettings &settings,
                    const std::string      &mesh_file,
                    ParameterHandler       &macro)
      {
        ElasticityParameters parameters =
          read_macro_problem(settings.macro_file,
                             settings.macro_settings,
                             macro);
        AssertThrow(parameters.dim == 2 && parameters.plane_stress,
                    ExcMessage("Two-scale/Macro problem: the homogenized "
                               "moduli are 2D; set Dimension = 2 and "
                               "Material/Plane = stress."));
        AssertThrow(parameters.design.blocks ==
                        std::vector<std::string>{"cell material"} &&
                      parameters.design.young_poisson,
                    ExcMessage("Two-scale/Macro problem: the design must be "
                               "'cell material' alone, in Young's modulus "
                               "and Poisson's ratio."));
        parameters.mesh.source               = "file";
        parameters.mesh.file                 = mesh_file;
        parameters.mesh.file_as_given        = "rhombic_mesh.msh";
        parameters.mesh.initial_refinement   = 0;
        parameters.mesh.convert_to_simplices = false; // cells are the quads
        return parameters;
      }



      /// The quad of each of the macro problem's cells: the simulator
      /// numbers cells its own way, so they are matched by center (within
      /// `tolerance`, squared).
      std::vector<unsigned int>
      match_quads(const std::vector<Point<2>> &quad_centers,
                  const std::vector<Point<2>> &simulator_centers,
                  const double                 tolerance)
      {
        const unsigned int n_cells = quad_centers.size();
        AssertThrow(simulator_centers.size() == n_cells,
                    ExcMessage("Two-scale/Macro problem: its mesh must be "
                               "the rhombic quad mesh, cell for cell (no "
                               "refinement or adaptivity)."));
        std::vector<unsigned int> quad_of(n_cells, 0);
        std::vector<bool>         matched(n_cells, false);
        for (unsigned int g = 0; g < n_cells; ++g)
          {
            double best = 1e300;
            for (unsigned int c = 0; c < n_cells; ++c)
              if (quad_centers[c].distance_square(simulator_centers[g]) < best)
                {
                  best = quad_centers[c].distance_square(simulator_centers[g]);
                  quad_of[g] = c;
                }
            AssertThrow(best < tolerance && !matched[quad_of[g]],
                        ExcMessage("Two-scale: a cell of the macro problem "
                                   "matches no quad of the rhombic mesh."));
            matched[quad_of[g]] = true;
          }
        return quad_of;
      }



      /// The design per quad of the rhombic mesh (in its order): the
      /// materials and the map's structures.
      struct CellDesign
      {
        std::vector<double>           E, nu;
        std::vector<RhombicStructure> structures;
      };



      /// Each cell's structure from the map (ch. 4.6), inside D(alpha), for
      /// the macro problem's materials (in its cell order).
      CellDesign
      structures_from_map(const std::vector<std::array<double, 2>> &materials,
                          const std::vector<unsigned int>          &quad_of,
                          const MapCells                           &cells,
                          const MaterialMap                        &map,
                          const Setup                              &setup)
      {
        const unsigned int n_cells = quad_of.size();
        CellDesign         d;
        d.E.resize(n_cells);
        d.nu.resize(n_cells);
        d.structures.resize(n_cells);
        for (unsigned int g = 0; g < n_cells; ++g)
          {
            const unsigned int c = quad_of[g];
            d.E[c]               = materials[g][0];
            d.nu[c]              = materials[g][1];
            bool inside          = false;
            d.structures[c] =
              map.query(d.E[c], d.nu[c], cells.alpha[c], setup.base.nu, inside);
          }
        return d;
      }



      /// Fig. 4.22: structures made for squares (the map at 90 degrees) on
      /// the same quads, checked at the fine scale.
      void
      remapped_square_baseline(const std::vector<Quad> &quads,
                               const CellDesign        &design,
                               const MaterialMap       &map,
                               const Setup             &setup,
                               const Tiler             &tile,
                               const FineScaleCheck    &fine_scale,
                               LoadCases<2>            &homogenized)
      {
        std::vector<RhombicStructure> squares(quads.size());
        for (unsigned int c = 0; c < quads.size(); ++c)
          {
            bool inside = false;
            squares[c] =
              map.query(design.E[c], design.nu[c], 90, setup.base.nu, inside);
          }
        const TiledObject remapped = tile(quads, squares);
        fine_scale([&remapped](const Point<2> &x) { return remapped(x); },
                   remapped.lo,
                   remapped.hi,
                   "remapped_square",
                   homogenized);
      }



      /// Fig. 4.23: the same quads and materials, each quad given the
      /// table's structure nearest to its material, mapped onto it.
      void
      pointwise_table_baseline(const std::vector<Quad> &quads,
                               const CellDesign        &design,
                               const PointwiseTable    &table,
                               const TiledObject       &family,
                               const TwoScaleSettings  &settings,
                               const Tiler             &tile,
                               const FineScaleCheck    &fine_scale,
                               LoadCases<2>            &homogenized,
                               RunContext              &context)
      {
        const unsigned int            n_cells = quads.size();
        std::vector<RhombicStructure> looked_up(n_cells);
        double                        dE = 0, dnu = 0;
        for (unsigned int c = 0; c < n_cells; ++c)
          {
            const auto &e = table.nearest(design.E[c], design.nu[c]);
            looked_up[c]  = e.structure;
            dE += std::abs(e.E / design.E[c] - 1) / n_cells;
            dnu += std::abs(e.nu - design.nu[c]) / n_cells;
          }
        context.print(
          "pointwise table: " + std::to_string(table.entries.size()) +
          " structures; nearest entry |E/E* - 1| mean " + sig(dE, 2) +
          ", |nu - nu*| mean " + sig(dnu, 2));
        const TiledObject pointwise = tile(quads, looked_up);
        fine_scale([&pointwise](const Point<2> &x) { return pointwise(x); },
                   pointwise.lo,
                   pointwise.hi,
                   "pointwise_table",
                   homogenized);
        context.print("pointwise table: joint radii p5 of neighbours "
                      "differ by up to " +
                      sig(pointwise.largest_joint_mismatch, 2) +
                      (settings.merge ? " (merged)" : "") +
                      "; the family's by up to " +
                      sig(family.largest_joint_mismatch, 2));
        context.summary["pointwise_table"] = {
          {"largest_joint_mismatch", pointwise.largest_joint_mismatch},
          {"family_largest_joint_mismatch", family.largest_joint_mismatch},
          {"entries", table.entries.size()},
          {"mean_lookup_E_error", dE},
          {"mean_lookup_nu_error", dnu}};
      }



      /// The summary's cells: center, angle, material and structure.
      nlohmann::json
      cells_summary(const MapCells &cells, const CellDesign &design)
      {
        nlohmann::json json = nlohmann::json::array();
        for (unsigned int c = 0; c < cells.centers.size(); ++c)
          {
            const auto         &p = design.structures[c].p;
            std::vector<double> parameters(p.begin(), p.end());
            json.push_back(
              {{"center", {cells.centers[c][0], cells.centers[c][1]}},
               {"alpha", cells.alpha[c]},
               {"E_relative", design.E[c]},
               {"nu", design.nu[c]},
               {"parameters", parameters}});
          }
        return json;
      }


      /// The map's grid as bounds on the cell materials: E/E_b lo, hi and
      /// nu lo, hi (nu sheared by the base material's, as the map is).
      std::array<double, 4>
      map_box(const MaterialMap &map, const Setup &setup)
      {
        return {{map.E.front(),
                 map.E.back(),
                 map.nu.front() + setup.base.nu * map.E.front(),
                 map.nu.back() + setup.base.nu * map.E.back()}};
      }



      /// Step 2's outcome: the materials in the simulator's cell order,
      /// that order's quads, the design and what the projection moved.
      struct MacroMaterials
      {
        std::vector<std::array<double, 2>> materials;
        std::vector<unsigned int>          quad_of;
        std::vector<double>                q;
        Projection                         projection;
      };



      /// Per-cell materials for the macro problem (ch. 4.8), optimized or
      /// constant, inside each quad's D(alpha).
      MacroMaterials
      macro_materials(const TwoScaleSettings      &settings,
                      const ElasticityParameters  &parameters,
                      ParameterHandler            &macro,
                      const MapCells              &cells,
                      const double                 cell_measure,
                      const std::array<double, 4> &box,
                      const Setup                 &setup,
                      RunContext                  &context)
      {
        MacroMaterials     m;
        const unsigned int n_cells = cells.centers.size();
        CoverageConstraint coverage{
          "cell material",
          setup.base.E,
          settings.coverage_weight,
          box,
          [&](const std::vector<Point<2>> &simulator_centers) {
            m.quad_of = match_quads(cells.centers,
                                    simulator_centers,
                                    1e-10 * cell_measure);
            std::vector<const Region *> regions;
            for (const unsigned int c : m.quad_of)
              regions.push_back(&cells.region[c]);
            return regions;
          },
          0,
          {}};
        if (settings.constant_material.empty())
          context.print("material optimization on the rhombic mesh (" +
                        std::to_string(n_cells) + " cells)");
        m.materials = design_materials(coverage,
                                       parameters,
                                       macro,
                                       context,
                                       settings.constant_material,
                                       m.q,
                                       m.projection);
        if (!settings.constant_material.empty())
          {
            const auto e =
              Utilities::split_string_list(settings.constant_material);
            context.print("constant material E/E_b = " + e[0] +
                          ", nu = " + e[1] + " in all " +
                          std::to_string(n_cells) + " cells");
          }
        return m;
      }



      /// The materials' range and what the projection moved.
      void
      print_materials(const CellDesign     &design,
                      const MacroMaterials &m,
                      const MapCells       &cells,
                      RunContext           &context)
      {
        const auto &E = design.E, &nu = design.nu;
        context.print("materials: E/E_b " +
                      sig(*std::min_element(E.begin(), E.end()), 3) + "-" +
                      sig(*std::max_element(E.begin(), E.end()), 3) + ", nu " +
                      sig(*std::min_element(nu.begin(), nu.end()), 3) + "-" +
                      sig(*std::max_element(nu.begin(), nu.end()), 3) + "; " +
                      m.projection.describe("cells", [&](const unsigned int g) {
                        return "cell " + std::to_string(m.quad_of[g]) + " (" +
                               sig(cells.alpha[m.quad_of[g]], 3) + " degrees)";
                      }));
      }



      /// Runs one baseline; one that cannot be built, meshed or solved is
      /// reported, not fatal: the design is the family's.
      void
      run_baseline(const std::string           &name,
                   const std::function<void()> &run,
                   RunContext                  &context)
      {
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
      }



      /// What the fine-scale checks need besides the family's design.
      struct FineScaleInputs
      {
        const Triangulation<2, 2>  &tria;
        const PolygonDomain        &domain;
        const ElasticityParameters &parameters;
        ParameterHandler           &macro;
        const MaterialMap          &map;
        const PointwiseTable       &table;
        const std::array<double, 4> box;
      };



      /// Step 4 (ch. 4.8): the tiled geometry meshed and simulated in the
      /// base material with the same supports and loads, against the
      /// homogenized solution (per-cell materials) on the compared
      /// boundary; then the baselines of ch. 4.8, each against its own
      /// homogenized solution. Returns the family's tiling.
      TiledObject
      fine_scale_checks(const FineScaleInputs     &in,
                        const CellDesign          &design,
                        const std::vector<double> &q,
                        const TwoScaleSettings    &settings,
                        const Setup               &setup,
                        RunContext                &context,
                        const std::function<void(const std::string &)> &lap)
      {
        const unsigned int n_cells = in.tria.n_active_cells();
        double             h       = 0; // the quads' mean size
        for (const auto &cell : in.tria.active_cell_iterators())
          h += std::sqrt(cell->measure()) / n_cells;
        // Tilings, optionally of subdivided cells (Fig. 4.21).
        const unsigned int      n_sub = 1u << settings.refinement;
        const Tiler             tile{n_sub, settings.merge};
        const FineScaleCheck    fine_scale(settings,
                                        in.domain,
                                        in.parameters,
                                        setup,
                                        context,
                                        h,
                                        h / n_sub,
                                        lap);
        const std::vector<Quad> quads = quads_of(in.tria);
        const TiledObject       tiled = tile(quads, design.structures);
        if (!settings.fine_check)
          return tiled;
        const auto homogenized =
          solved(in.parameters, q, context.communicator());
        fine_scale([&tiled](const Point<2> &x) { return tiled(x); },
                   tiled.lo,
                   tiled.hi,
                   "family",
                   *homogenized);
        const auto wanted = [&](const std::string &name) {
          return settings.baselines.count(name) > 0;
        };
        if (wanted("remapped square"))
          run_baseline(
            "remapped_square",
            [&]() {
              remapped_square_baseline(
                quads, design, in.map, setup, tile, fine_scale, *homogenized);
            },
            context);
        if (wanted("pointwise table"))
          run_baseline(
            "pointwise_table",
            [&]() {
              pointwise_table_baseline(quads,
                                       design,
                                       in.table,
                                       tiled,
                                       settings,
                                       tile,
                                       fine_scale,
                                       *homogenized,
                                       context);
            },
            context);
        if (wanted("cut grid"))
          run_baseline(
            "cut_grid",
            [&]() {
              cut_grid_baseline(in.tria,
                                in.domain,
                                in.parameters,
                                in.map,
                                setup,
                                settings,
                                in.box,
                                in.macro,
                                context,
                                lap,
                                tile,
                                fine_scale);
            },
            context);
        return tiled;
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
      const PointwiseTable table = read_baseline_table(settings, setup);
      const MaterialMap    map   = read_map(prm, prm_directory);

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
      const MapCells cells = map_cells(tria, shape, map, setup, context);
      lap("rhombic mesh");

      // 2. Per-cell materials for the macro problem (ch. 4.8).
      ParameterHandler           macro;
      const ElasticityParameters parameters =
        macro_problem(settings, mesh_file, macro);
      const std::array<double, 4> box = map_box(map, setup);
      const MacroMaterials        m   = macro_materials(settings,
                                               parameters,
                                               macro,
                                               cells,
                                               tria.begin_active()->measure(),
                                               box,
                                               setup,
                                               context);
      lap("materials");

      // 3. Each cell's structure from the map (ch. 4.6), inside D(alpha).
      const CellDesign design =
        structures_from_map(m.materials, m.quad_of, cells, map, setup);
      print_materials(design, m, cells, context);
      lap("map");
      if (settings.check_moduli)
        {
          check_cell_moduli(
            design.structures, design.E, design.nu, setup, context);
          lap("cell moduli");
        }

      // 4. The fine-scale checks of the family and the baselines.
      const TiledObject tiled =
        fine_scale_checks({tria, domain, parameters, macro, map, table, box},
                          design,
                          m.q,
                          settings,
                          setup,
                          context,
                          lap);
      context.summary["seconds"]   = seconds;
      context.summary["cells"]     = cells_summary(cells, design);
      context.summary["two_scale"] = {{"cells", tria.n_active_cells()},
                                      {"clamped_angles", cells.clamped},
                                      {"projected_cells", m.projection.outside},
                                      {"largest_coverage_violation",
                                       m.projection.worst}};
      write_design_outputs(tria,
                           design.E,
                           design.nu,
                           cells.alpha,
                           design.structures,
                           map,
                           box,
                           tiled,
                           context);
    }
  } // namespace rhombic
} // namespace forma
