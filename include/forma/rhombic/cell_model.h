#ifndef forma_rhombic_cell_model_h
#define forma_rhombic_cell_model_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/symmetric_tensor.h>

#include <forma/rhombic/study.h>

#include <array>
#include <memory>

namespace forma
{
  class LevelSetMeshMotion;

  namespace rhombic
  {
    /**
     * One rhombic structure's cell problem with its shape derivative
     * (thesis ch. 4.5.1): the cell mesh of the structure, C^H, and
     * dC^H/dp for the 8 parameters. The derivative is exact for the
     * discrete design-to-C^H map that keeps the mesh's topology and moves
     * its vertices (LevelSetMeshMotion); move_to() evaluates that map at
     * another design, which is what a Taylor test needs. Optimizers remesh
     * instead (a new CellModel per design) and use the same gradient.
     */
    class CellModel
    {
    public:
      CellModel(const RhombicStructure &structure,
                const Setup            &setup,
                const MPI_Comm          comm);
      ~CellModel();

      /// C^H (diagonal axes) and the rest of the sample on the current mesh.
      const Sample &
      sample() const
      {
        return current;
      }

      struct Gradient
      {
        /// dC^H/dp_i (diagonal axes)
        std::array<dealii::SymmetricTensor<4, 2>,
                   RhombicStructure::n_parameters>
          C;
        /// d(volume fraction)/dp_i
        std::array<double, RhombicStructure::n_parameters> phi;
      };

      /// Derivatives with respect to p1..p8 at the meshed design.
      Gradient
      gradient() const;

      /**
       * Move the mesh to `other` (same angle and blending, parameters close
       * to the current ones) without remeshing, and homogenize there.
       */
      void
      move_to(const RhombicStructure &other);

      const RhombicStructure &
      structure() const
      {
        return design;
      }

      /// The mesh and the fluctuations, in the rhombus's coordinates.
      void
      write_vtu(const std::string &file_stem) const;

      /**
       * The material of the cell as closed outlines (the mesh's boundary
       * loops, the cell's sides included, so that copies tile), in the
       * rhombus's coordinates scaled to a side of `side` millimetres: an SVG
       * path or a DXF, by the file name's extension, e.g. for a laser cutter.
       */
      void
      write_outline(const std::string &file_name, const double side) const;

    private:
      void
      homogenize();

      /// The mesh motion of the meshed design, built on first use.
      const LevelSetMeshMotion &
      motion() const;

      RhombicStructure                             start, design;
      const Setup                                  setup;
      const MPI_Comm                               comm;
      std::unique_ptr<dealii::Triangulation<2, 2>> mesh;
      mutable std::unique_ptr<LevelSetMeshMotion>  motion_;
      std::unique_ptr<PeriodicHomogenization<2>>   cell;
      Sample                                       current;
    };
  } // namespace rhombic
} // namespace forma

#endif
