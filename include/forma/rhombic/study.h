#ifndef forma_rhombic_study_h
#define forma_rhombic_study_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/symmetric_tensor.h>

#include <forma/base/records.h>
#include <forma/homogenization/base_material.h>
#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/periodic_homogenization.h>
#include <forma/mesh/level_set_mesh.h>
#include <forma/microstructure/rhombic_structure.h>
#include <forma/rhombic/material_map.h>
#include <forma/rhombic/quad_mesh_optimization.h>

#include <nlohmann/json.hpp>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace dealii
{
  class ParameterHandler;
  template <int dim, int spacedim>
  class Triangulation;
} // namespace dealii

namespace forma
{
  class RunContext;

  /**
   * The forma-rhombic application (thesis ch. 4) as library pieces: its
   * parameters, the homogenization of one rhombic structure on a periodic
   * P2 mesh of its level set through the reference square (ch. 4.5.2), and
   * the modes, each in its own source file.
   */
  namespace rhombic
  {
    /// Base material, cell mesh and solver: what every mode shares.
    struct Setup
    {
      BaseMaterial material;
      /// material.moduli() (parse_setup() sets both; a Setup made by hand
      /// must keep them together): the 2D moduli results are relative to.
      IsotropicModuli        base;
      double                 blending = 0.01;
      LevelSetMeshParameters mesh;
      unsigned int           degree = 2;
      /// Mesh half the cell and rotate a copy (every structure of the
      /// family is symmetric under the rotation by pi): odd fluctuations,
      /// half the unknowns.
      bool                                        symmetric_mesh = true;
      PeriodicHomogenization<2>::SolverParameters solver;
      bool                                        write_vtu = true;
      /// Side of the cell in structure.svg, in millimetres.
      double svg_cell_side = 20;
      /// a1, a2 at most this: the structure counts as isotropic (thesis
      /// ch. 4.6.2 uses 0.005).
      double isotropy_tolerance = 0.005;
    };

    /// What one homogenized structure gives; C in the rhombus's diagonal
    /// axes (long diagonal along x), where it is orthotropic.
    struct Sample
    {
      double                        phi = 0;
      dealii::SymmetricTensor<4, 2> C, C_reference;
      IsotropicModuli               fit;
      OrthotropicModuli             orthotropic;
      Anisotropy                    anisotropy;
      LevelSetMeshInfo              mesh;
      unsigned int                  cells = 0, vertices = 0;
      unsigned long long            dofs = 0;
      /// Wall seconds: meshing, homogenization set-up, solve (logs only).
      double seconds_mesh = 0, seconds_setup = 0, seconds_solve = 0;
    };

    /// Mesh the structure's cell (the root meshes, all ranks of `comm`
    /// solve) and homogenize it; CellModel keeps the mesh and fields.
    Sample
    evaluate(const RhombicStructure &structure,
             const Setup            &setup,
             const MPI_Comm          comm);

    /// The Structure section (range-checked).
    RhombicStructure
    read_structure(dealii::ParameterHandler &prm, const Setup &setup);

    nlohmann::json
    structure_json(const RhombicStructure &s);

    /// Tensors, moduli, anisotropy, mesh and CLM moduli of a sample.
    nlohmann::json
    sample_json(const Sample &r, const Setup &setup);

    /// A picture of `tiles` x `tiles` cells of the structure (material dark,
    /// the cell outlined), `pixels` wide.
    void
    write_structure_png(const std::string      &file_name,
                        const RhombicStructure &structure,
                        const unsigned int      tiles  = 3,
                        const unsigned int      pixels = 600);

    /// Every section and entry of the application's parameter file.
    void
    declare_parameters(dealii::ParameterHandler &prm);

    /// Setup from the Base material, Mesh, Solver and Output sections
    /// (recorded in the summary).
    Setup
    parse_setup(dealii::ParameterHandler &prm, RunContext &context);

    /// One structure -> summary.json, structure.png, cell.vtu.
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

    /// Throws unless every E/E_b is in (0, 1) and every nu in (-1, 1); the
    /// messages name `section` (e.g. "Map").
    void
    check_target_grid(const std::vector<double> &Es,
                      const std::vector<double> &nus,
                      const std::string         &section);

    /// A picture of a 2D mesh with one value per active cell (blue at
    /// `range[0]` to red at `range[1]`) and the cell edges, `pixels` wide,
    /// with a color bar labelled `label`.
    void
    write_cell_field_png(const std::string                 &file_name,
                         const dealii::Triangulation<2, 2> &tria,
                         const std::vector<double>         &values,
                         const std::array<double, 2>       &range,
                         const std::string                 &label,
                         const unsigned int                 pixels = 800);

    /// A parameter grid -> samples.csv, coverage.png (resumable).
    void
    sweep_mode(dealii::ParameterHandler &prm,
               const Setup              &setup,
               RunContext               &context);
  } // namespace rhombic
} // namespace forma

#endif
