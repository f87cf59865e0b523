#ifndef forma_mesh_level_set_mesh_h
#define forma_mesh_level_set_mesh_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>

#include <functional>
#include <string>

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
}

namespace forma
{
  struct LevelSetMeshParameters
  {
    /// Marching squares cells along the box's longer side (thesis: 256;
    /// the projection makes the boundary exact, so the grid only needs to
    /// resolve the topology).
    unsigned int grid = 128;
    /// Largest element edge inside the material.
    double size = 0.05;
    /// Element edge along the material boundary.
    double boundary_size = 0.0125;
    /// Where the resampled boundary crosses itself or a hole (a gap or a
    /// joint thinner than `boundary_size`), thicken the material there,
    /// phi -= boundary_size (1 - r^2 / R^2)^2 within R = 4 boundary_size
    /// of the crossing, and trace again; at most this many crossings in
    /// all (0: a crossing is an error). Each moves the boundary by about
    /// boundary_size (|grad phi| = 1), only within R of its crossing.
    unsigned int max_thickenings = 0;
    /// Mesh only the largest piece of material (not periodic): the others
    /// are loose in an object (dropped and counted as islands).
    bool largest_piece_only = false;
    /// Periodic cells whose level set is symmetric under the rotation by pi
    /// about the box's center, phi(box - x) = phi(x) (spot-checked; an
    /// error if not): trace and mesh the lower half y <= box_1 / 2 only and
    /// add its rotated copy, so the mesh has the symmetry too
    /// (PeriodicHomogenization's `inversion_symmetric` then halves the
    /// unknowns) at half the meshing cost. The joint y = box_1 / 2 is
    /// sampled at `size` (it is inside the material, away from the
    /// boundary's stress concentrations). A hole across the joint is
    /// meshed whatever its size (the half sees it as a notch in its side).
    bool centrally_symmetric = false;
  };

  struct LevelSetMeshInfo
  {
    double       area            = 0; ///< of the meshed material
    unsigned int boundary_loops  = 0; ///< closed chains of boundary edges
    unsigned int dropped_islands = 0; ///< floating material pieces removed
    unsigned int dropped_holes   = 0; ///< holes smaller than an element
    unsigned int thickenings     = 0; ///< see max_thickenings
  };

  /**
   * A conforming triangle mesh of the material {phi < 0} of the periodic
   * box [0, box] (thesis ch. 4.5.1: marching squares, then a constrained
   * mesher; here Gmsh). The zero contour is traced by marching squares on a
   * periodic grid, resampled to `boundary_size` and every vertex is
   * projected onto phi = 0 (Newton steps along the gradient), so the
   * boundary is exact at the vertices whatever the grid. The parts of the
   * box's sides inside the material are subdivided identically on opposite
   * sides (one element per boundary segment), so the nodes match as
   * PeriodicHomogenization's mesh constructor needs.
   *
   * Material pieces that touch no side of the box cannot carry load in a
   * periodic structure (they float): they are dropped and counted, as are
   * holes smaller than an element.
   *
   * `phi` must be periodic on the box. Gmsh runs on the root of `comm`,
   * which sends the mesh to the other ranks; errors are thrown on every
   * rank with a message naming `context`.
   */
  void
  periodic_level_set_mesh(
    const std::function<double(const dealii::Point<2> &)> &phi,
    const dealii::Point<2>                                &box,
    const LevelSetMeshParameters                          &parameters,
    dealii::Triangulation<2, 2>                           &tria,
    const MPI_Comm                                         comm = MPI_COMM_SELF,
    LevelSetMeshInfo                                      *info = nullptr,
    const std::string                                     &context = "cell");

  /**
   * The same for a level set that is not periodic: a conforming triangle
   * mesh of {phi < 0}, which must lie inside the box [lower, upper] (phi > 0
   * on its sides), e.g. a whole object of tiled microstructure cells. Every
   * contour with positive area bounds a piece of material; holes smaller
   * than an element are dropped and counted.
   */
  void
  level_set_mesh(const std::function<double(const dealii::Point<2> &)> &phi,
                 const dealii::Point<2>                                &lower,
                 const dealii::Point<2>                                &upper,
                 const LevelSetMeshParameters &parameters,
                 dealii::Triangulation<2, 2>  &tria,
                 const MPI_Comm                comm    = MPI_COMM_SELF,
                 LevelSetMeshInfo             *info    = nullptr,
                 const std::string            &context = "object");
} // namespace forma

#endif
