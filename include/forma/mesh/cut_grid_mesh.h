#ifndef forma_mesh_cut_grid_mesh_h
#define forma_mesh_cut_grid_mesh_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>

#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
}

namespace forma
{
  class PolygonDomain;

  /**
   * A conforming triangle mesh (Gmsh, OpenCASCADE boolean fragments) of
   * `domain` cut by the regular square grid of side `spacing` with a corner
   * at `origin` (the cut-regular-grid cells of the thesis's ch. 4.8
   * baseline): element edges follow the grid lines and the domain's sides,
   * material id k marks the part of grid square k, whose lower-left corner
   * is squares[k] (squares that meet the domain, row by row), and boundary
   * faces get the id of the domain side they lie on.
   *
   * `size` is the target element size. Gmsh runs on the root of `comm`,
   * which sends the mesh to the other ranks; errors are thrown on every
   * rank.
   */
  void
  cut_grid_mesh(const PolygonDomain           &domain,
                const dealii::Point<2>        &origin,
                const double                   spacing,
                const double                   size,
                dealii::Triangulation<2, 2>   &tria,
                std::vector<dealii::Point<2>> &squares,
                const MPI_Comm                 comm = MPI_COMM_SELF);
} // namespace forma

#endif
