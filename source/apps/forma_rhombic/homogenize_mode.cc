#include <deal.II/base/parameter_handler.h>

#include <forma/base/run_context.h>
#include <forma/homogenization/bounds.h>
#include <forma/rhombic/cell_model.h>

#include "modes.h"

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    void
    homogenize_mode(ParameterHandler &prm,
                    const Setup      &setup,
                    RunContext       &context)
    {
      const RhombicStructure s = read_structure(prm, setup);
      context.print("rhombic cell: alpha = " + sig(s.alpha * 180 / M_PI) +
                    " degrees, p = " + [&] {
                      std::string t;
                      for (const double v : s.p)
                        t += (t.empty() ? "" : ", ") + sig(v);
                      return t;
                    }());
      const CellModel model(s, setup, context.communicator());
      const Sample   &r = model.sample();
      context.log("seconds: mesh " + sig(r.seconds_mesh, 3) + ", set-up " +
                  sig(r.seconds_setup, 3) + ", solve " +
                  sig(r.seconds_solve, 3));
      context.print("mesh: " + std::to_string(r.vertices) + " vertices, " +
                    std::to_string(r.cells) + " triangles, P" +
                    std::to_string(setup.degree) + ": " +
                    std::to_string(r.dofs) + " dofs; " +
                    std::to_string(r.mesh.boundary_loops) +
                    " boundary loops; volume fraction " + sig(r.phi, 5));
      if (r.mesh.dropped_islands + r.mesh.dropped_holes > 0)
        context.print(
          "mesh: dropped " + std::to_string(r.mesh.dropped_islands) +
          " floating pieces and " + std::to_string(r.mesh.dropped_holes) +
          " holes smaller than an element");
      const VoigtMatrix V = to_voigt(r.C);
      for (unsigned int i = 0; i < 3; ++i)
        context.print(std::string(i == 0 ? "C^H (Voigt, diagonal axes): " :
                                           "                            ") +
                      "[" + sig(V[i][0], 5) + ", " + sig(V[i][1], 5) + ", " +
                      sig(V[i][2], 5) + "]");
      context.print("E1 = " + sig(r.orthotropic.E1, 5) +
                    ", E2 = " + sig(r.orthotropic.E2, 5) +
                    ", G12 = " + sig(r.orthotropic.G12, 5) +
                    ", nu12 = " + sig(r.orthotropic.nu12, 5));
      context.print("isotropic fit: E/E_b = " + sig(r.fit.E / setup.base.E, 5) +
                    ", nu = " + sig(r.fit.nu, 5) +
                    "; anisotropy a1 = " + sig(r.anisotropy.a1, 3) +
                    ", a2 = " + sig(r.anisotropy.a2, 3) +
                    (r.anisotropy.a1 <= setup.isotropy_tolerance &&
                         r.anisotropy.a2 <= setup.isotropy_tolerance ?
                       " (isotropic)" :
                       " (not isotropic)"));
      for (const auto &[nu, m] : setup.material.clm_fits(r.C))
        context.print("CLM, base nu = " + sig(nu) + ": E = " + sig(m.E, 5) +
                      ", nu = " + sig(m.nu, 5));
      write_cell_results(context, s, model, setup);
    }



    void
    write_cell_results(RunContext             &context,
                       const RhombicStructure &s,
                       const CellModel        &model,
                       const Setup            &setup)
    {
      context.summary["structure"] = structure_json(s);
      context.summary["result"]    = sample_json(model.sample(), setup);
      if (context.is_root())
        {
          write_structure_png(context.path("structure.png"), s);
          model.write_outline(context.path("structure.svg"),
                              setup.svg_cell_side);
          model.write_outline(context.path("structure.dxf"),
                              setup.svg_cell_side);
        }
      if (setup.write_vtu)
        model.write_vtu(context.path("cell"));
    }
  } // namespace rhombic
} // namespace forma
