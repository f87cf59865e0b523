#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/grid/grid_out.h>
#include <deal.II/grid/tria.h>
#include <deal.II/lac/vector.h>
#include <deal.II/numerics/data_out.h>

#include <forma/adjoint/design.h>
#include <forma/base/application.h>
#include <forma/base/plot.h>
#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/elasticity/jobs.h>
#include <forma/elasticity/load_cases.h>
#include <forma/elasticity/parameters.h>
#include <forma/elasticity/simulator.h>
#include <forma/ipc/ipc_parameters.h>
#include <forma/mesh/level_set_mesh.h>
#include <forma/rhombic/material_map.h>
#include <forma/rhombic/study.h>
#include <forma/rhombic/tiling.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <memory>
#include <tuple>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    namespace
    {
      constexpr double degrees = 180 / M_PI;

      /// The tiled geometry: every cell's structure mapped onto its quad
      /// (material dark), the quads outlined.
      void
      write_geometry_png(const std::string                   &file_name,
                         const Triangulation<2, 2>           &tria,
                         const std::vector<RhombicStructure> &structures,
                         const int                            width = 1200)
      {
        double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
        for (const auto &cell : tria.active_cell_iterators())
          for (unsigned int k = 0; k < 4; ++k)
            for (unsigned int d = 0; d < 2; ++d)
              {
                lo[d] = std::min(lo[d], cell->vertex(k)[d]);
                hi[d] = std::max(hi[d], cell->vertex(k)[d]);
              }
        const int    margin = 10;
        const double scale  = (width - 2 * margin) / (hi[0] - lo[0]);
        const int    height =
          2 * margin + static_cast<int>(std::ceil((hi[1] - lo[1]) * scale));
        std::vector<unsigned char> rgb(3 * width * height, 255);
        unsigned int               c = 0;
        for (const auto &cell : tria.active_cell_iterators())
          {
            const auto v       = acute_first(quad_of_cell(cell));
            const auto phi     = structures[c++].level_set();
            double     b_lo[2] = {1e300, 1e300}, b_hi[2] = {-1e300, -1e300};
            for (const Point<2> &p : v)
              for (unsigned int d = 0; d < 2; ++d)
                {
                  b_lo[d] = std::min(b_lo[d], p[d]);
                  b_hi[d] = std::max(b_hi[d], p[d]);
                }
            const int
              x0 = std::max(0, int((b_lo[0] - lo[0]) * scale) + margin - 1),
              x1 = std::min(width - 1,
                            int((b_hi[0] - lo[0]) * scale) + margin + 1),
              y0 = std::max(0, int((hi[1] - b_hi[1]) * scale) + margin - 1),
              y1 = std::min(height - 1,
                            int((hi[1] - b_lo[1]) * scale) + margin + 1);
            for (int y = y0; y <= y1; ++y)
              for (int x = x0; x <= x1; ++x)
                {
                  const Point<2> X(lo[0] + (x + 0.5 - margin) / scale,
                                   hi[1] - (y + 0.5 - margin) / scale);
                  Point<2>       xi;
                  if (reference_point(v, X, xi) &&
                      phi(Point<2>(RhombicStructure::side * xi)) < 0)
                    for (unsigned int k = 0; k < 3; ++k)
                      rgb[3 * (y * width + x) + k] = 40;
                }
          }
        write_image_png(file_name, width, height, rgb);
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
        write_overlay_png(file_name, deformed(fine), deformed(homogenized));
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
      read_macro_problem(const std::string &file, ParameterHandler &macro)
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
        ElasticityParameters p;
        p.parse(macro,
                std::filesystem::path(file).parent_path().string(),
                false,
                true);
        return p;
      }

      /// Closest point of the convex region to m (alternating projections
      /// onto the violated half-planes).
      std::array<double, 2>
      project(std::array<double, 2>                      m,
              const std::vector<MaterialMap::HalfPlane> &region)
      {
        for (unsigned int it = 0; it < 200; ++it)
          {
            bool moved = false;
            for (const auto &h : region)
              {
                const double v = h.c_E * m[0] + h.c_nu * m[1] - h.d;
                if (v > 1e-12)
                  {
                    m[0] -= v * h.c_E;
                    m[1] -= v * h.c_nu;
                    moved = true;
                  }
              }
            if (!moved)
              break;
          }
        return m;
      }

      double
      violation(const std::array<double, 2>               &m,
                const std::vector<MaterialMap::HalfPlane> &region)
      {
        double v = 0;
        for (const auto &h : region)
          v = std::max(v, h.c_E * m[0] + h.c_nu * m[1] - h.d);
        return v;
      }
    } // namespace



    void
    two_scale_design_mode(ParameterHandler  &prm,
                          const std::string &prm_directory,
                          const Setup       &setup,
                          RunContext        &context)
    {
      prm.enter_subsection("Two-scale");
      std::string  macro_file      = prm.get("Macro problem");
      const double coverage_weight = prm.get_double("Coverage weight");
      const bool   fine_check      = prm.get_bool("Fine-scale check");
      const double fine_size       = prm.get_double("Fine element size");
      const double fine_boundary_size =
        prm.get_double("Fine boundary element size");
      const int compared_boundary = prm.get_integer("Compared boundary");
      const std::string constant_material = prm.get("Constant material");
      const bool        check_moduli      = prm.get_bool("Check cell moduli");
      const bool        fine_simulation = prm.get_bool("Fine-scale simulation");
      prm.leave_subsection();
      if (!macro_file.empty() && macro_file[0] != '/')
        macro_file = prm_directory + "/" + macro_file;
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
      const std::string mesh_file = context.path("rhombic_mesh.msh");
      MPI_Barrier(context.communicator()); // the root wrote it

      // Each quad's angle, clamped to the map's range, and its region D.
      const unsigned int  n_cells = tria.n_active_cells();
      std::vector<double> alpha(n_cells);
      std::vector<std::vector<MaterialMap::HalfPlane>> region(n_cells);
      std::vector<Point<2>>                            centers;
      unsigned int                                     clamped = 0;
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
      ElasticityParameters parameters = read_macro_problem(macro_file, macro);
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
      std::vector<unsigned int> quad_of;
      const double              E_b = setup.base.E;
      const double E_lo = E_b * map.E.front(), E_hi = E_b * map.E.back();
      const double nu_lo      = map.nu.front() + setup.base.nu * map.E.front(),
                   nu_hi      = map.nu.back() + setup.base.nu * map.E.back();
      constexpr double tau    = 0.01; // violation scale in (E/E_b, nu)
      unsigned int     offset = 0;    // of the cell material block
      DesignConstraint constraint;
      constraint.setup = [&](const DesignLayout          &layout,
                             const std::vector<Point<2>> &simulator_centers,
                             std::vector<double>         &lower,
                             std::vector<double>         &upper) {
        const DesignBlock *b = layout.find("cell material");
        offset               = b->offset;
        AssertThrow(simulator_centers.size() == n_cells,
                    ExcMessage("Two-scale/Macro problem: its mesh must be the "
                               "rhombic quad mesh, cell for cell (no "
                               "refinement or adaptivity)."));
        quad_of.assign(simulator_centers.size(), 0);
        std::vector<bool> matched(n_cells, false);
        for (unsigned int g = 0; g < simulator_centers.size(); ++g)
          {
            double best = 1e300;
            for (unsigned int c = 0; c < n_cells; ++c)
              if (centers[c].distance_square(simulator_centers[g]) < best)
                {
                  best       = centers[c].distance_square(simulator_centers[g]);
                  quad_of[g] = c;
                }
            AssertThrow(best < 1e-10 * tria.begin_active()->measure() &&
                          !matched[quad_of[g]],
                        ExcMessage("Two-scale: a cell of the macro problem "
                                   "matches no quad of the rhombic mesh."));
            matched[quad_of[g]]      = true;
            lower[b->offset + 2 * g] = std::max(lower[b->offset + 2 * g], E_lo);
            upper[b->offset + 2 * g] = std::min(upper[b->offset + 2 * g], E_hi);
            lower[b->offset + 2 * g + 1] =
              std::max(lower[b->offset + 2 * g + 1], nu_lo);
            upper[b->offset + 2 * g + 1] =
              std::min(upper[b->offset + 2 * g + 1], nu_hi);
          }
      };
      constraint.penalty = [&](const std::vector<double> &q,
                               std::vector<double>       &dP) {
        const double w = coverage_weight / quad_of.size();
        double       P = 0;
        for (unsigned int g = 0; g < quad_of.size(); ++g)
          {
            std::array<double, 2> grad = {{0, 0}};
            P += w * coverage_penalty({{q[offset + 2 * g] / E_b,
                                        q[offset + 2 * g + 1]}},
                                      region[quad_of[g]],
                                      tau,
                                      grad);
            dP[offset + 2 * g] += w * grad[0] / E_b;
            dP[offset + 2 * g + 1] += w * grad[1];
          }
        return P;
      };
      std::vector<double> q;
      if (constant_material.empty())
        {
          context.print("material optimization on the rhombic mesh (" +
                        std::to_string(n_cells) + " cells)");
          q = run_elasticity_job(
            "optimize", parameters, macro, context, &constraint);
        }
      else
        {
          // One material everywhere (e.g. mesh independence, Fig. 4.25).
          const auto m = Utilities::split_string_list(constant_material);
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
          for (unsigned int g = 0; g < quad_of.size(); ++g)
            {
              q[offset + 2 * g]     = E_b * Utilities::string_to_double(m[0]);
              q[offset + 2 * g + 1] = Utilities::string_to_double(m[1]);
            }
          context.print("constant material E/E_b = " + m[0] + ", nu = " + m[1] +
                        " in all " + std::to_string(n_cells) + " cells");
        }

      lap("materials");

      // 3. Each cell's structure from the map (ch. 4.6), inside D(alpha).
      std::vector<RhombicStructure> structures(n_cells);
      std::vector<double>           E(n_cells), nu(n_cells);
      double                        worst   = 0;
      unsigned int                  outside = 0;
      for (unsigned int g = 0; g < quad_of.size(); ++g)
        {
          const unsigned int          c = quad_of[g];
          const std::array<double, 2> m = {
            {q[offset + 2 * g] / E_b, q[offset + 2 * g + 1]}};
          const double v = violation(m, region[c]);
          worst          = std::max(worst, v);
          outside += v > 1e-6;
          const auto p = project(m, region[c]);
          E[c]         = p[0];
          nu[c]        = p[1];
          bool inside  = false;
          structures[c] =
            map.query(E[c], nu[c], alpha[c], setup.base.nu, inside);
          // The homogenized reference gets the materials the cells are
          // built for.
          q[offset + 2 * g]     = E_b * E[c];
          q[offset + 2 * g + 1] = nu[c];
        }
      context.print("materials: E/E_b " +
                    sig(*std::min_element(E.begin(), E.end()), 3) + "-" +
                    sig(*std::max_element(E.begin(), E.end()), 3) + ", nu " +
                    sig(*std::min_element(nu.begin(), nu.end()), 3) + "-" +
                    sig(*std::max_element(nu.begin(), nu.end()), 3) + "; " +
                    std::to_string(outside) +
                    " cells projected into the coverage (largest distance " +
                    sig(worst, 2) + ")");

      lap("map");

      // The cells' structures homogenized: how far the map's structures are
      // from their targets (identical structures are homogenized once).
      if (check_moduli)
        {
          std::map<std::vector<double>, Sample> done;
          double mean_E = 0, max_E = 0, mean_nu = 0, max_nu = 0, mean_a = 0;
          for (unsigned int c = 0; c < n_cells; ++c)
            {
              // Rounded: the same structure from round-off-different fits.
              std::vector<double> key;
              for (const double v : structures[c].p)
                key.push_back(std::round(v * 1e9));
              key.push_back(std::round(structures[c].alpha * 1e9));
              if (!done.count(key))
                done[key] =
                  evaluate(structures[c], setup, context.communicator());
              const Sample &r  = done.at(key);
              const double  eE = std::abs(r.fit.E / setup.base.E / E[c] - 1);
              const double  en = std::abs(r.fit.nu - nu[c]);
              mean_E += eE / n_cells;
              mean_nu += en / n_cells;
              max_E  = std::max(max_E, eE);
              max_nu = std::max(max_nu, en);
              mean_a += std::max(r.anisotropy.a1, r.anisotropy.a2) / n_cells;
            }
          context.print(
            "cell structures homogenized (" + std::to_string(done.size()) +
            " distinct): |E/E* - 1| mean " + sig(mean_E, 3) + ", max " +
            sig(max_E, 3) + "; |nu - nu*| mean " + sig(mean_nu, 3) + ", max " +
            sig(max_nu, 3) + "; anisotropy max(a1, a2) mean " + sig(mean_a, 3));
          lap("cell moduli");
          context.summary["cell_moduli"] = {{"distinct_structures",
                                             done.size()},
                                            {"mean_relative_E_error", mean_E},
                                            {"max_relative_E_error", max_E},
                                            {"mean_nu_error", mean_nu},
                                            {"max_nu_error", max_nu},
                                            {"mean_anisotropy", mean_a}};
        }

      // 4. Fine-scale check (ch. 4.8): the tiled geometry meshed and
      // simulated in the base material with the same supports and loads,
      // against the homogenized solution (per-cell materials) on the
      // compared boundary.
      // The family against the baseline of ch. 4.8 (Fig. 4.22): structures
      // made for squares (the map at 90 degrees) mapped onto the quads.
      std::unique_ptr<LoadCases<2>> homogenized;
      const auto fine_scale = [&](const std::vector<RhombicStructure> &tiles,
                                  const std::string                   &name) {
        if (!homogenized)
          {
            homogenized =
              std::make_unique<LoadCases<2>>(parameters,
                                             context.communicator());
            homogenized->prepare(nullptr);
            if (!parameters.objective.terms.empty())
              homogenized->set_objective(parameters.objective);
            homogenized->set_design(q);
            homogenized->solve_design();
          }
        double h = 0;
        for (const auto &cell : tria.active_cell_iterators())
          h += std::sqrt(cell->measure()) / n_cells;
        const TiledObject      object(quads_of(tria), tiles);
        LevelSetMeshParameters fine;
        fine.size                = fine_size * h;
        fine.boundary_size       = fine_boundary_size * h;
        const Tensor<1, 2> pad   = Tensor<1, 2>({0.25 * h, 0.25 * h});
        const Point<2>     lower = object.lo - pad, upper = object.hi + pad;
        fine.grid = std::min<unsigned int>(
          8192,
          static_cast<unsigned int>(std::ceil(
            std::max(upper[0] - lower[0], upper[1] - lower[1]) / (0.02 * h))));
        Triangulation<2> fine_tria;
        LevelSetMeshInfo info;
        level_set_mesh(object,
                       lower,
                       upper,
                       fine,
                       fine_tria,
                       context.communicator(),
                       &info,
                       "fine-scale geometry (" + name + ")");
        // Boundary ids from the quad mesh's boundary; holes: free.
        std::vector<std::tuple<Point<2>, Point<2>, types::boundary_id>> ids;
        for (const auto &cell : tria.active_cell_iterators())
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary())
              ids.emplace_back(cell->face(f)->vertex(0),
                               cell->face(f)->vertex(1),
                               cell->face(f)->boundary_id());
        // Holes get an id the quad mesh does not use: free.
        types::boundary_id free_id = 0;
        for (const auto &[a, b, i] : ids)
          free_id = std::max<types::boundary_id>(free_id, i + 1);
        std::map<unsigned int, Point<2>> compared_points;
        for (const auto &cell : fine_tria.active_cell_iterators())
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary())
              {
                const Point<2>     c    = cell->face(f)->center();
                types::boundary_id id   = free_id;
                double             best = 1e-3 * h;
                for (const auto &[a, b, i] : ids)
                  {
                    const Tensor<1, 2> e = b - a;
                    const double t = std::clamp((c - a) * e / (e * e), 0., 1.);
                    const double d = c.distance(a + t * e);
                    if (d < best)
                      {
                        best = d;
                        id   = i;
                      }
                  }
                cell->face(f)->set_boundary_id(id);
                // Vertices of the compared boundary, nudged into their
                // cell: on the boundary up to round-off, they could fall
                // just outside the other mesh.
                if (static_cast<int>(id) == compared_boundary)
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
                               std::to_string(compared_boundary) + "."));
        const std::string fine_file =
          context.path("fine_mesh_" + name + ".msh");
        if (context.is_root())
          {
            std::ofstream msh(fine_file);
            msh << std::setprecision(17); // read back by the simulator
            GridOut out;
            out.set_flags(GridOutFlags::Msh(/*write_faces=*/true));
            out.write_msh(fine_tria, msh);
          }
        MPI_Barrier(context.communicator());
        lap("fine mesh, " + name);
        context.summary["fine_scale"][name] = {
          {"triangles", fine_tria.n_active_cells()},
          {"dropped_islands", info.dropped_islands}};
        if (!fine_simulation)
          {
            context.log("fine scale, " + name + ": " +
                        std::to_string(fine_tria.n_active_cells()) +
                        " triangles (not simulated)");
            return;
          }

        ElasticityParameters fp = parameters;
        fp.mesh.file            = fine_file;
        fp.mesh.file_as_given   = "fine_mesh_" + name + ".msh";
        fp.bodies = "* : E = " + Utilities::to_string(setup.base.E, 17) +
                    ", nu = " + Utilities::to_string(setup.base.nu, 17);
        {
          std::map<types::boundary_id, double> macro_length, fine_length;
          for (const auto &cell : tria.active_cell_iterators())
            for (const unsigned int f : cell->face_indices())
              if (cell->face(f)->at_boundary())
                macro_length[cell->face(f)->boundary_id()] +=
                  cell->face(f)->measure();
          for (const auto &cell : fine_tria.active_cell_iterators())
            for (const unsigned int f : cell->face_indices())
              if (cell->face(f)->at_boundary())
                fine_length[cell->face(f)->boundary_id()] +=
                  cell->face(f)->measure();
          std::map<types::boundary_id, double> factor;
          for (const auto &[id, l] : fine_length)
            if (macro_length.count(id))
              factor[id] = macro_length[id] / l;
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
        ElasticitySimulator<2> fine_simulator(fp, context.communicator());
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
          (*homogenized)[0].cell_vertex_displacements();
        if (context.is_root())
          write_deformation_png(context.path("fine_scale_" + name + ".png"),
                                fine_cells,
                                homogenized_cells);

        double mean = 0, worst_error = 0, largest = 0;
        for (const auto &[v, x] : compared_points)
          {
            const Tensor<1, 2> uf = fine_simulator.point_displacement(x);
            const Tensor<1, 2> uh = (*homogenized)[0].point_displacement(x);
            mean += (uf - uh).norm() / compared_points.size();
            worst_error = std::max(worst_error, (uf - uh).norm());
            largest     = std::max(largest, uh.norm());
          }
        AssertThrow(largest > 0,
                    ExcMessage("Two-scale/Compared boundary " +
                               std::to_string(compared_boundary) +
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
                      std::to_string(compared_boundary) +
                      " |u_fine - u_homogenized| / max |u_homogenized|: mean " +
                      sig(mean / largest, 2) + ", max " +
                      sig(worst_error / largest, 2));
        lap("fine solve, " + name);
        context.summary["fine_scale"][name] = {
          {"triangles", fine_tria.n_active_cells()},
          {"dofs", fine_simulator.n_dofs()},
          {"dropped_islands", info.dropped_islands},
          {"compared_boundary", compared_boundary},
          {"compared_points", compared_points.size()},
          {"max_homogenized_displacement", largest},
          {"mean_relative_error", mean / largest},
          {"max_relative_error", worst_error / largest}};
      };
      if (fine_check)
        {
          fine_scale(structures, "family");
          std::vector<RhombicStructure> squares(n_cells);
          for (unsigned int c = 0; c < n_cells; ++c)
            {
              bool inside = false;
              squares[c]  = map.query(E[c], nu[c], 90, setup.base.nu, inside);
            }
          fine_scale(squares, "remapped_square");
        }
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
                                      {"projected_cells", outside},
                                      {"largest_coverage_violation", worst}};
      if (context.is_root())
        {
          write_cell_field_png(context.path("material_E.png"),
                               tria,
                               E,
                               {{map.E.front(), map.E.back()}},
                               "E / E_base (cell materials)");
          write_cell_field_png(context.path("material_nu.png"),
                               tria,
                               nu,
                               {{nu_lo, nu_hi}},
                               "Poisson ratio nu (cell materials)");
          write_geometry_png(context.path("geometry.png"), tria, structures);
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
        }
    }
  } // namespace rhombic
} // namespace forma
