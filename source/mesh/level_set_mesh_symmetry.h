#ifndef forma_source_mesh_level_set_mesh_symmetry_h
#define forma_source_mesh_level_set_mesh_symmetry_h

// Internal helpers of the level-set mesher (not installed).

#include <deal.II/base/point.h>
#include <deal.II/grid/tria.h>
#include <deal.II/grid/tria_description.h>

#include "gmsh_session.h"

#include <vector>

namespace forma
{
  namespace internal
  {
    /// Closed chains of boundary edges (contours and the parts of the box's
    /// sides in the material) of a mesh.
    unsigned int
    count_boundary_loops(const dealii::Triangulation<2> &tria);

    /**
     * The cell mesh from the mesh of its lower half (y <= L_1 / 2) and the
     * half's copy rotated by pi about the center, joined along y = L_1 / 2,
     * whose nodes are mirror-symmetric about x = L_0 / 2. Material that
     * reaches no side of the cell floats: its cells are dropped and the
     * pieces counted.
     */
    void
    join_rotated_copy(const GmshTriangles              &half,
                      const dealii::Point<2>           &box,
                      std::vector<dealii::Point<2>>    &vertices,
                      std::vector<dealii::CellData<2>> &cells,
                      unsigned int                     &floating_pieces);
  } // namespace internal
} // namespace forma

#endif
