#include <deal.II/base/parameter_handler.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <forma/base/plot.h>
#include <forma/base/records.h>
#include <forma/base/run_context.h>
#include <forma/homogenization/periodic_homogenization.h>
#include <forma/mesh/level_set_mesh.h>
#include <forma/rhombic/material_map.h>
#include <forma/rhombic/quad_mesh_optimization.h>
#include <forma/rhombic/tiling.h>

#include "modes.h"

#include <algorithm>
#include <array>
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

      /// The n x n grid of quads of side 2 (the reference cell's) on the
      /// periodic box [0, 2n]^2, deformed for one value of the study.
      void
      compound_mesh(const std::string                    &study,
                    const unsigned int                    n,
                    const double                          value,
                    const QuadMeshOptimizationParameters &optimization,
                    Triangulation<2, 2>                  &tria)
      {
        const double L = 2. * n;
        tria.clear();
        GridGenerator::subdivided_hyper_cube(tria, n, 0, L);
        const Point<2> center(L / 2, L / 2);
        if (study == "non-rhombic")
          {
            // Thesis Fig. 4.29: the center vertex moves towards the upper
            // right corner by `value` quad sides in each axis.
            for (const auto &cell : tria.active_cell_iterators())
              for (unsigned int v = 0; v < 4; ++v)
                if (cell->vertex(v).distance(center) < 1e-9)
                  cell->vertex(v) += Tensor<1, 2>({2 * value, 2 * value});
            return;
          }
        // Thesis Fig. 4.26: the cross of mesh lines through the center
        // turns by `value` degrees; the other interior vertices follow by
        // the rhombic optimization, the cross and the box's sides held.
        const double          r        = value / degrees;
        const auto           &vertices = tria.get_vertices();
        std::vector<bool>     fixed(vertices.size(), false);
        std::vector<Point<2>> turned(vertices);
        for (unsigned int i = 0; i < vertices.size(); ++i)
          {
            const Point<2> &p = vertices[i];
            const bool      on_side =
              std::min({p[0], p[1], L - p[0], L - p[1]}) < 1e-9;
            const bool on_cross =
              std::abs(p[0] - L / 2) < 1e-9 || std::abs(p[1] - L / 2) < 1e-9;
            fixed[i] = on_side || on_cross;
            if (on_cross && !on_side)
              {
                const Tensor<1, 2> d = p - center;
                turned[i] =
                  center +
                  Tensor<1, 2>({std::cos(r) * d[0] - std::sin(r) * d[1],
                                std::sin(r) * d[0] + std::cos(r) * d[1]});
              }
          }
        for (const auto &cell : tria.active_cell_iterators())
          for (unsigned int v = 0; v < 4; ++v)
            cell->vertex(v) = turned[cell->vertex_index(v)];
        optimize_rhombic_mesh(tria, optimization, fixed);
      }
      /// The Compound cell section, read and checked once.
      struct CompoundSettings
      {
        std::string                    study;
        unsigned int                   n = 0, n_sub = 1;
        std::vector<double>            values, material;
        QuadMeshOptimizationParameters optimization;
      };



      CompoundSettings
      read_compound_settings(ParameterHandler &prm)
      {
        CompoundSettings s;
        prm.enter_subsection("Compound cell");
        s.study = prm.get("Study");
        s.n     = prm.get_integer("Grid");
        s.values =
          parse_numbers(prm.get("Values"), "Compound cell/Values", -90, 90);
        s.material =
          parse_numbers(prm.get("Material"), "Compound cell/Material", -1, 10);
        s.n_sub = 1u << prm.get_integer("Refinement");
        prm.leave_subsection();
        const auto &m = s.material;
        AssertThrow(m.size() == 2 && m[0] > 0 && m[1] > -1 && m[1] < 1,
                    ExcMessage("Compound cell/Material: give 'E/E_b, nu' with "
                               "E/E_b > 0 and -1 < nu < 1 (2D moduli)."));
        AssertThrow(!s.values.empty(),
                    ExcMessage("Compound cell/Values: give at least one."));
        AssertThrow(s.study != "non-rhombic" || s.n % 2 == 0,
                    ExcMessage("Compound cell/Grid: the non-rhombic study "
                               "moves the center vertex; use an even grid."));
        AssertThrow(s.study != "twist" || (s.n % 2 == 0 && s.n >= 4),
                    ExcMessage("Compound cell/Grid: the twist study turns the "
                               "cross through the center of an even grid of "
                               "at least 4 x 4."));
        prm.enter_subsection("Quad mesh");
        s.optimization.parse(prm);
        prm.leave_subsection();
        return s;
      }



      /**
       * C^H of the compound cell (side L) whose quads are filled with the
       * map's structures for the target material: at each quad's own
       * angle (`family`) or at 90 degrees (structures made for squares).
       */
      SymmetricTensor<4, 2>
      tiled_moduli(const std::vector<Quad> &quads,
                   const bool               family,
                   const CompoundSettings  &s,
                   const MaterialMap       &map,
                   const Setup             &setup,
                   const MPI_Comm           comm)
      {
        const double                  angle_lo = map.covered_angles()[0];
        const double                  L        = 2. * s.n;
        std::vector<RhombicStructure> structures(quads.size());
        for (unsigned int c = 0; c < quads.size(); ++c)
          {
            const double a = fit_rhombus(quads[c]).angle * degrees;
            const double alpha =
              family ? std::max(std::min(a, 180 - a), angle_lo) : 90.;
            bool inside   = false;
            structures[c] = map.query(
              s.material[0], s.material[1], alpha, setup.base.nu, inside);
          }
        const TiledObject object(
          quads, structures, Tensor<1, 2>({L, L}), false, false);
        // The marching squares grid counts along the box: n times the
        // single cell's; sub-quads are meshed like the cell scaled.
        LevelSetMeshParameters mesh_parameters = setup.mesh;
        mesh_parameters.grid = std::min(8192u, setup.mesh.grid * s.n * s.n_sub);
        mesh_parameters.size /= s.n_sub;
        mesh_parameters.boundary_size /= s.n_sub;
        Triangulation<2> mesh;
        periodic_level_set_mesh(object,
                                Point<2>(L, L),
                                mesh_parameters,
                                mesh,
                                comm,
                                nullptr,
                                "compound cell");
        PeriodicHomogenization<2> cell(
          comm, mesh, Point<2>(L, L), setup.solver, setup.degree);
        const SymmetricTensor<4, 2> base = setup.base.tensor();
        return cell
          .homogenize(
            [&](const Point<2> &, const types::material_id) { return base; })
          .C;
      }



      /// compound_cell.csv and compound_cell.png (Fig. 4.27, 4.30).
      void
      write_compound_outputs(const nlohmann::json              &rows,
                             std::vector<std::array<double, 2>> family_points,
                             std::vector<std::array<double, 2>> square_points,
                             const std::string                 &study,
                             const RunContext                  &context)
      {
        std::ofstream csv(context.path("compound_cell.csv"));
        csv << "value,rhombic_error,error_family,error_squares\n";
        for (const auto &r : rows)
          csv << double(r["value"]) << ',' << double(r["rhombic_error"]) << ','
              << double(r["error_family"]) << ',' << double(r["error_squares"])
              << '\n';
        double top = 0;
        for (const auto &r : rows)
          top = std::max(
            {top, double(r["error_family"]), double(r["error_squares"])});
        // Values in any order: the lines follow them sorted.
        std::sort(family_points.begin(), family_points.end());
        std::sort(square_points.begin(), square_points.end());
        const std::array<double, 2> x_range = {
          {family_points.front()[0], family_points.back()[0]}};
        PlotSeries f, q;
        f.points = family_points;
        f.line   = true;
        f.label  = "family P(E, ν, α)";
        q.points = square_points;
        q.line   = true;
        q.color  = {{200, 60, 40}};
        q.label  = "structures for squares";
        write_xy_plot(context.path("compound_cell.png"),
                      {f, q},
                      study == "twist" ? "twisted compound cell (Fig. 4.27)" :
                                         "non-rhombic cells (Fig. 4.30)",
                      study == "twist" ? "turn of the cross (°)" :
                                         "center offset (quad sides)",
                      "relative error of C",
                      x_range,
                      {{0, top > 0 ? 1.1 * top : 1.}});
      }
    } // namespace



    void
    compound_cell_mode(ParameterHandler  &prm,
                       const std::string &prm_directory,
                       const Setup       &setup,
                       RunContext        &context)
    {
      const CompoundSettings      s   = read_compound_settings(prm);
      const MaterialMap           map = read_map(prm, prm_directory);
      const double                nu  = s.material[1];
      const SymmetricTensor<4, 2> target =
        IsotropicModuli::from_young_poisson(s.material[0] * setup.base.E, nu)
          .tensor();
      context.print("compound cell: " + std::to_string(s.n) + " x " +
                    std::to_string(s.n) + " quads, " + s.study +
                    " study, target "
                    "E/E_b = " +
                    sig(s.material[0]) + ", nu = " + sig(nu));
      context.print(
        std::string(s.study == "twist" ? "turn (deg)" : "    offset") +
        "   rhombic error  error (family)  error (squares)  "
        "E/E_b (family)  nu (family)");

      nlohmann::json                     rows = nlohmann::json::array();
      std::vector<std::array<double, 2>> family_points, square_points;
      for (const double value : s.values)
        {
          Triangulation<2, 2> tria;
          compound_mesh(s.study, s.n, value, s.optimization, tria);
          const QuadMeshShape shape = quad_mesh_shape(tria);
          AssertThrow(shape.min_scaled_jacobian > 0,
                      ExcMessage("Compound cell/Values: " + sig(value) +
                                 " folds a quad of the compound cell."));
          double rhombic_error = 0;
          for (const double e : shape.rhombic_error)
            rhombic_error += e;
          // Refined (Fig. 4.28): children of the oriented quads keep their
          // parent's orientation, each gets the angle of its own rhombus.
          std::vector<Quad> oriented;
          for (const Quad &q : quads_of(tria))
            oriented.push_back(acute_first(q));
          std::vector<unsigned int> parent;
          const std::vector<Quad> quads = subdivide(oriented, s.n_sub, parent);
          std::array<double, 2>   error = {{0, 0}};
          IsotropicModuli         fit;
          for (const bool family : {true, false})
            {
              const SymmetricTensor<4, 2> C = tiled_moduli(
                quads, family, s, map, setup, context.communicator());
              error[family ? 0 : 1] = (C - target).norm() / target.norm();
              if (family)
                fit = isotropic_fit(C);
            }
          std::ostringstream line;
          line << std::setw(10) << sig(value) << std::setw(16)
               << (rhombic_error < 1e-9 ? std::string("0") :
                                          sig(rhombic_error, 3))
               << std::setw(16) << sig(error[0], 2) << std::setw(17)
               << sig(error[1], 2) << std::setw(16)
               << sig(fit.E / setup.base.E, 3) << std::setw(13)
               << sig(fit.nu, 2);
          context.print(line.str());
          rows.push_back({{"value", value},
                          {"rhombic_error", rhombic_error},
                          {"min_alpha", shape.min_alpha * degrees},
                          {"error_family", error[0]},
                          {"error_squares", error[1]},
                          {"E_relative_family", fit.E / setup.base.E},
                          {"nu_family", fit.nu}});
          family_points.push_back({{value, error[0]}});
          square_points.push_back({{value, error[1]}});
        }
      context.summary["compound_cell"] = {{"study", s.study},
                                          {"grid", s.n},
                                          {"target", s.material},
                                          {"rows", rows}};
      if (context.is_root())
        write_compound_outputs(
          rows, family_points, square_points, s.study, context);
    }
  } // namespace rhombic
} // namespace forma
