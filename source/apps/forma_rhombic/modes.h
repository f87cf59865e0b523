#ifndef forma_apps_forma_rhombic_modes_h
#define forma_apps_forma_rhombic_modes_h

// forma-rhombic's modes and the helpers only they use (the application's
// own code, not the library's): each reads its sections and runs on the
// library's rhombic study (forma/rhombic/study.h).

#include <deal.II/grid/tria.h>

#include <forma/base/run_context.h>
#include <forma/rhombic/material_map.h>
#include <forma/rhombic/quad_mesh_optimization.h>
#include <forma/rhombic/study.h>

#include <string>

namespace forma
{
  namespace rhombic
  {
    /// One structure -> summary.json, structure.png, cell.vtu.
    class CellModel;

    /// A homogenized cell's result files: summary entries "structure" and
    /// "result", structure.png and .svg, and the fields if asked for.
    void
    write_cell_results(RunContext             &context,
                       const RhombicStructure &s,
                       const CellModel        &model,
                       const Setup            &setup);

    void
    homogenize_mode(dealii::ParameterHandler &prm,
                    const Setup              &setup,
                    RunContext               &context);

    /// A target (E, nu) -> structure parameters by bound-constrained
    /// L-BFGS (ROL) with shape derivatives, remeshing every design.
    void
    inverse_mode(dealii::ParameterHandler &prm,
                 const Setup              &setup,
                 RunContext               &context);

    /// Taylor test of dJ/dp for the Inverse section's objective.
    void
    verify_gradient_mode(dealii::ParameterHandler &prm,
                         const Setup              &setup,
                         RunContext               &context);

    /// The material-to-geometry map by continuation -> map.json (or the
    /// extension of an existing map to smaller angles).
    void
    build_map_mode(dealii::ParameterHandler &prm,
                   const std::string        &prm_directory,
                   const Setup              &setup,
                   RunContext               &context);

    /// (E, nu, alpha) -> structure parameters from a map, verified by
    /// homogenization.
    void
    query_mode(dealii::ParameterHandler &prm,
               const std::string        &prm_directory,
               const Setup              &setup,
               RunContext               &context);

    /// A quad mesh (Quad mesh section) -> nearly rhombic quads (thesis ch.
    /// 4.7): rhombic_mesh.msh, VTU and PNG of the cells' angles.
    void
    rhombic_mesh_mode(dealii::ParameterHandler &prm,
                      const std::string        &prm_directory,
                      RunContext               &context);

    /// What rhombic_mesh_mode() does, for the pipeline: `tria` becomes the
    /// optimized mesh (also written); returns its cells' shapes.
    QuadMeshShape
    make_rhombic_mesh(dealii::ParameterHandler    &prm,
                      const std::string           &prm_directory,
                      RunContext                  &context,
                      dealii::Triangulation<2, 2> &tria);

    /**
     * The two-scale pipeline (thesis ch. 4.7-4.8): the Quad mesh section's
     * mesh made rhombic; per-cell (E, nu) optimized for the Two-scale/Macro
     * problem (a forma-transient-ipc parameter file: loads, supports,
     * objective, `cell material` design, Optimization section) with each
     * cell's material kept inside the map's coverage D(alpha) of its angle;
     * each cell's structure from the Map section's material-to-geometry
     * map; pictures of the materials and of the tiled geometry.
     */
    void
    two_scale_design_mode(dealii::ParameterHandler &prm,
                          const std::string        &prm_directory,
                          const Setup              &setup,
                          RunContext               &context);

    /**
     * The compound-cell studies of thesis ch. 4.8 (Fig. 4.26-4.30): an
     * n x n grid of quads on a periodic box, deformed (`non-rhombic`: the
     * center vertex moved; `twist`: the cross through the center turned,
     * the rest optimized by optimize_rhombic_mesh), every quad filled with
     * the map's structure for one target material, at its own angle (the
     * family) or at 90 degrees (structures for squares); the compound
     * cell is homogenized and compared with the target tensor.
     */
    void
    compound_cell_mode(dealii::ParameterHandler &prm,
                       const std::string        &prm_directory,
                       const Setup              &setup,
                       RunContext               &context);

    /// The material-to-geometry map named by Map/Map file (relative to the
    /// parameter file).
    MaterialMap
    read_map(dealii::ParameterHandler &prm, const std::string &prm_directory);

    /// The Quad mesh section's mesh (a .msh file or a meshed .geo), refined
    /// as asked and flattened to one level.
    void
    read_quad_mesh(dealii::ParameterHandler    &prm,
                   const std::string           &prm_directory,
                   dealii::Triangulation<2, 2> &tria);

    /// A parameter grid -> samples.csv, coverage.png (resumable).
    void
    sweep_mode(dealii::ParameterHandler &prm,
               const Setup              &setup,
               RunContext               &context);
  } // namespace rhombic
} // namespace forma

#endif
