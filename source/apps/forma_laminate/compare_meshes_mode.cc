#include <deal.II/base/exceptions.h>
#include <deal.II/base/numbers.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>
#include <deal.II/grid/tria.h>

#include <forma/base/run_context.h>
#include <forma/laminate/shape_derivative.h>

#include "modes.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

namespace forma
{
  namespace laminate
  {
    using namespace dealii;

    /**
     * Regular grid vs conforming mesh (thesis Table 5.2): the structure's
     * polygons meshed by Gmsh with periodic sides (P`degree` triangles),
     * then on the regular grid at the same parameters, then on the grid
     * with p4 (theta for limit structures) adjusted until E matches the
     * conforming result, comparing nu.
     */
    void
    compare_meshes_mode(ParameterHandler &prm,
                        const Setup      &setup,
                        RunContext       &context)
    {
      const HexagonalLaminate s = read_structure(prm);
      prm.enter_subsection("Conforming mesh");
      const double       size   = prm.get_double("Element size");
      const unsigned int degree = prm.get_integer("Degree");
      prm.leave_subsection();
      const Point<2> box(HexagonalLaminate::width, HexagonalLaminate::height);
      context.print("structure: " + s.family_name() +
                    (s.limit ? " limit" : "") + ", volume fraction " +
                    sig(s.volume_fraction_formula()));

      // Conforming mesh: material id 0 is void, k + 1 phase k.
      Triangulation<2> mesh;
      conforming_mesh(s, size, mesh, context.communicator());
      std::vector<double> density;
      const auto tensor   = phase_tensors(s, setup.base, setup.weak, density);
      const auto weak     = setup.weak.tensor();
      auto phase_material = [&](const Point<2> &, const types::material_id id) {
        AssertThrow(id <= tensor.size(), ExcInternalError());
        return id == 0 ? weak : tensor[id - 1];
      };
      PeriodicHomogenization<2> conforming(context.communicator(),
                                           mesh,
                                           setup.solver,
                                           degree);
      Timer                     timer;
      const auto C_mesh = conforming.homogenize(phase_material).C;
      context.log("conforming mesh homogenization: " + sig(timer.wall_time()) +
                  " s wall");
      double phi_mesh = 0;
      for (const auto &cell : mesh.active_cell_iterators())
        if (cell->material_id() > 0)
          phi_mesh += density[cell->material_id() - 1] * cell->measure();
      phi_mesh /= box[0] * box[1];
      const auto mesh_fit = isotropic_fit(C_mesh);
      context.print("conforming mesh: " + std::to_string(conforming.n_cells()) +
                    " P" + std::to_string(degree) + " triangles, " +
                    std::to_string(conforming.n_unknowns()) +
                    " unknowns: E/Eb = " + sig(mesh_fit.E / setup.base.E) +
                    ", nu = " + sig(mesh_fit.nu) + ", volume fraction " +
                    sig(phi_mesh));

      // The regular grid at the same parameters.
      const unsigned int ny   = setup.cells_along_height;
      const unsigned int nx   = grid_nx(ny);
      const auto         grid = family_grid(MPI_COMM_SELF, setup, ny);
      auto               at   = [&](const double value) {
        HexagonalLaminate t        = s;
        (t.limit ? t.theta : t.p4) = value;
        t.check();
        return evaluate(
          *grid,
          pixel_material(t, setup.base, setup.weak, setup.gray, nx, ny),
          setup);
      };
      const std::string name  = s.limit ? "theta" : "p4";
      const double      value = s.limit ? s.theta : s.p4;
      const Sample      same  = at(value);
      context.print(
        "regular " + std::to_string(nx) + " x " + std::to_string(ny) +
        " grid: E/Eb = " + sig(same.fit.E / setup.base.E) +
        ", nu = " + sig(same.fit.nu) + ", volume fraction " + sig(same.phi));

      // Match E by adjusting the beam width: secant steps kept inside a
      // bracket (E grows with it).
      const double target = mesh_fit.E;
      double       lo = 0.02, hi = 1, x = value;
      Sample       r      = same;
      double       x_prev = value, f_prev = same.fit.E - target;
      x = std::clamp(value + (f_prev > 0 ? -0.02 : 0.02), lo, hi);
      unsigned int iterations = 0;
      for (; iterations < 30; ++iterations)
        {
          r                 = at(x);
          const double f    = r.fit.E - target;
          (f > 0 ? hi : lo) = x;
          if (std::abs(f) <= 1e-5 * target || hi - lo < 1e-9)
            break;
          double next = x - f * (x - x_prev) / (f - f_prev);
          if (!(next > lo && next < hi) || !std::isfinite(next))
            next = 0.5 * (lo + hi);
          x_prev = x, f_prev = f, x = next;
        }
      const bool matched = std::abs(r.fit.E - target) <= 1e-3 * target;
      context.print(
        "grid matching E: " + name + " = " + sig(x) + " (mesh " + sig(value) +
        "): E/Eb = " + sig(r.fit.E / setup.base.E) + ", nu = " + sig(r.fit.nu) +
        "; nu(grid) - nu(mesh) = " + sig(r.fit.nu - mesh_fit.nu, 2) +
        (matched ? "" : " (E NOT matched in [0.02, 1])"));

      Sample mesh_sample;
      mesh_sample.phi = mesh_sample.phi_formula = phi_mesh;
      mesh_sample.C                             = C_mesh;
      mesh_sample.fit                           = mesh_fit;
      mesh_sample.anisotropy                    = anisotropy(C_mesh);
      mesh_sample.hs =
        hashin_shtrikman(setup.base, setup.weak, std::min(1., phi_mesh));
      mesh_sample.hs_violation           = mesh_sample.hs.violation(mesh_fit);
      context.summary["structure"]       = structure_json(s);
      context.summary["conforming_mesh"] = {
        {"element_size", size},
        {"degree", degree},
        {"cells", conforming.n_cells()},
        {"unknowns", conforming.n_unknowns()},
        {"volume_fraction", phi_mesh},
        {"result", sample_json(mesh_sample, setup)}};
      context.summary["grid"]         = {{"cells", {nx, ny}},
                                         {"result", sample_json(same, setup)}};
      context.summary["matched_grid"] = {{"parameter", name},
                                         {"value", x},
                                         {"matched", matched},
                                         {"E", r.fit.E},
                                         {"nu", r.fit.nu},
                                         {"nu_difference",
                                          r.fit.nu - mesh_fit.nu},
                                         {"iterations", iterations + 1}};
      if (setup.write_vtu)
        conforming.write_vtu(
          context.path("fields_mesh"),
          {"material_id", "density"},
          [&](const Point<2> &, const types::material_id id) {
            return std::vector<double>{double(id),
                                       id == 0 ? 0. : density[id - 1]};
          });
    }
  } // namespace laminate
} // namespace forma
