#include <deal.II/base/exceptions.h>
#include <deal.II/base/numbers.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/utilities.h>

#include <forma/base/run_context.h>
#include <forma/microstructure/density_image.h>

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

    namespace
    {
      /// Grid/Adaptive cycles: refine by the cell problems' stress jumps and
      /// homogenize again; one line and one summary record per cycle.
      Sample
      refine_adaptively(PeriodicHomogenization<2> &cell,
                        const PixelMaterial       &material,
                        const Setup               &setup,
                        Sample                     r,
                        RunContext                &context)
      {
        const auto fn = [&](const Point<2> &x, const types::material_id id) {
          return material(x, id);
        };
        nlohmann::json cycles = nlohmann::json::array();
        auto           record = [&](const unsigned int k) {
          cycles.push_back({{"cycle", k},
                            {"cells", cell.n_cells()},
                            {"unknowns", cell.n_unknowns()},
                            {"E", r.fit.E},
                            {"nu", r.fit.nu}});
          context.print("[cycle " + std::to_string(k) + "/" +
                        std::to_string(setup.adaptive_cycles) + "] " +
                        std::to_string(cell.n_cells()) + " cells, " +
                        std::to_string(cell.n_unknowns()) + " unknowns: E = " +
                        sig(r.fit.E, 6) + ", nu = " + sig(r.fit.nu, 6));
        };
        record(0);
        for (unsigned int k = 1; k <= setup.adaptive_cycles; ++k)
          {
            cell.refine(fn, setup.refine_fraction);
            r = evaluate(cell, material, setup);
            record(k);
          }
        context.summary["adaptive_cycles"] = cycles;
        return r;
      }
    } // namespace



    void
    homogenize_mode(ParameterHandler  &prm,
                    const std::string &prm_directory,
                    const Setup       &setup,
                    RunContext        &context)
    {
      prm.enter_subsection("Structure");
      const std::string type = prm.get("Type");
      prm.leave_subsection();

      std::unique_ptr<PeriodicHomogenization<2>> cell;
      std::unique_ptr<PixelMaterial>             material;
      nlohmann::json                             structure;
      if (type == "image")
        {
          prm.enter_subsection("Structure");
          std::string  file   = prm.get("Image file");
          const double width  = prm.get_double("Image width"),
                       height = prm.get_double("Image height");
          const bool invert   = prm.get_bool("Invert image");
          prm.leave_subsection();
          AssertThrow(!file.empty(),
                      ExcMessage(
                        "Structure/Type = image needs Structure/Image file"));
          if (file[0] != '/')
            file = prm_directory + "/" + file;
          const DensityImage image = DensityImage::read(file, invert);
          AssertThrow(image.mean() > 1e-6,
                      ExcMessage("the structure image '" + file +
                                 "' is empty (all densities are 0): nothing to "
                                 "homogenize"));
          // One grid cell per pixel; the raster is the image.
          PhaseRaster raster(image.nx, image.ny, width, height, 1);
          for (unsigned int j = 0; j < image.ny; ++j)
            for (unsigned int i = 0; i < image.nx; ++i)
              {
                const double x0 = width * i / image.nx,
                             x1 = width * (i + 1) / image.nx,
                             y0 = height * j / image.ny,
                             y1 = height * (j + 1) / image.ny;
                const double d  = image.density(i, j);
                if (d > 0)
                  {
                    // A rectangle of area d inside the pixel.
                    raster.add({Point<2>(x0, y0),
                                Point<2>(x0 + d * (x1 - x0), y0),
                                Point<2>(x0 + d * (x1 - x0), y1),
                                Point<2>(x0, y1)},
                               0);
                  }
              }
          material =
            std::make_unique<PixelMaterial>(std::move(raster),
                                            std::vector<double>{1},
                                            std::vector<SymmetricTensor<4, 2>>{
                                              setup.base.tensor()},
                                            setup.base,
                                            setup.weak,
                                            setup.gray);
          cell = std::make_unique<PeriodicHomogenization<2>>(
            context.communicator(),
            Point<2>(width, height),
            std::array<unsigned int, 2>{{image.nx, image.ny}},
            setup.solver);
          structure = {{"type", "image"},
                       {"pixels", {image.nx, image.ny}},
                       {"width", width},
                       {"height", height}};
          context.print("structure: image " + std::to_string(image.nx) + " x " +
                        std::to_string(image.ny) + " pixels");
        }
      else
        {
          const HexagonalLaminate s  = read_structure(prm);
          const unsigned int      ny = setup.cells_along_height;
          const unsigned int      nx = grid_nx(ny);
          material                   = std::make_unique<PixelMaterial>(
            pixel_material(s, setup.base, setup.weak, setup.gray, nx, ny));
          // Refinement breaks the odd symmetry: the whole rectangle.
          Setup grid_setup = setup;
          grid_setup.symmetry &= setup.adaptive_cycles == 0;
          cell      = family_grid(context.communicator(), grid_setup, ny);
          structure = structure_json(s);
          const double feature           = s.min_feature_size() * ny / s.height;
          structure["min_feature_cells"] = feature;
          if (feature < setup.min_feature_cells)
            context.print("warning: the thinnest beam, gap or joint spans " +
                          sig(feature, 2) +
                          " grid cells: under-resolved, the result is too "
                          "stiff (refine Grid/Cells along height)");
          context.print("structure: " + s.family_name() +
                        (s.limit ? " limit" : "") + ", volume fraction " +
                        sig(s.volume_fraction_formula()) +
                        " (eq. 5.11), lamination angle " +
                        sig(s.lamination_angle() * 180 / numbers::PI) + " deg");
        }
      const bool half =
        type != "image" && cell->volume() < 0.75 * HexagonalLaminate::width *
                                              HexagonalLaminate::height;
      context.print("grid: " + std::to_string(cell->n_cells()) + " cells, " +
                    std::to_string(cell->n_unknowns()) + " unknowns" +
                    (half ? " (the primitive half cell)" : ""));
      Timer  timer;
      Sample r = evaluate(*cell, *material, setup);
      if (setup.adaptive_cycles > 0)
        r = refine_adaptively(*cell, *material, setup, r, context);
      context.log("homogenization: " + sig(timer.wall_time()) + " s wall");
      context.print("E = " + sig(r.fit.E) + ", nu = " + sig(r.fit.nu) +
                    ", kappa = " + sig(r.fit.kappa) + ", mu = " +
                    sig(r.fit.mu) + ", volume fraction " + sig(r.phi));
      context.print("anisotropy a1 = " + sig(r.anisotropy.a1, 2) +
                    ", a2 = " + sig(r.anisotropy.a2, 2) +
                    "; Hashin-Shtrikman: E_max(nu) = " +
                    sig(r.hs.max_young_modulus(r.fit.nu)) +
                    (r.hs_violation <= 0 ? ", inside" : ", OUTSIDE"));
      if (type != "image" && r.anisotropy.residual > setup.isotropy_tolerance)
        context.print("warning: isotropy residual " +
                      sig(r.anisotropy.residual, 2) +
                      " for an isotropic structure: the grid does not "
                      "resolve it (refine Grid/Cells along height)");
      context.summary["structure"] = structure;
      context.summary["grid"]      = {{"cells", cell->n_cells()},
                                      {"unknowns", cell->n_unknowns()},
                                      {"dofs", cell->n_dofs()}};
      context.summary["result"]    = sample_json(r, setup);
      if (setup.write_vtu)
        cell->write_vtu(context.path("fields"),
                        {"density"},
                        [&](const Point<2> &x, const types::material_id) {
                          return std::vector<double>{material->density_at(x)};
                        });
    }
  } // namespace laminate
} // namespace forma
