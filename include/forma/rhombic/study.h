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

    /// Throws unless every E/E_b is in (0, 1) and every nu in (-1, 1); the
    /// messages name `section` (e.g. "Map").
    void
    check_target_grid(const std::vector<double> &Es,
                      const std::vector<double> &nus,
                      const std::string         &section);

    /// A picture of a 2D mesh (PNG, SVG or PDF by the file name) with one
    /// value per active cell (blue at `range[0]` to red at `range[1]`) and
    /// the cell edges, `width` wide, with a color bar; its numbers go to
    /// the CSV beside it (write_polygon_field()).
    void
    write_cell_field(const std::string                 &file_name,
                     const dealii::Triangulation<2, 2> &tria,
                     const std::vector<double>         &values,
                     const std::array<double, 2>       &range,
                     const std::string                 &label,
                     const unsigned int                 width = 800);

  } // namespace rhombic
} // namespace forma

#endif
