#ifndef forma_mesh_periodic_phase_mesh_h
#define forma_mesh_periodic_phase_mesh_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>

#include <utility>
#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
}

namespace forma
{
  /**
   * A conforming triangle mesh (Gmsh, OpenCASCADE boolean fragments) of the
   * periodic box [0, box] whose element edges follow the boundaries of the
   * given polygons: the part of polygon phase k gets material id k + 1, the
   * rest of the box material id 0. Polygons may reach out of the box (their
   * outside parts are dropped; a periodic structure passes its periodic
   * images). The nodes on opposite sides of the box match (Gmsh periodic
   * meshing), as PeriodicHomogenization needs.
   *
   * `size` is the target element size. Gmsh runs on the root of `comm`,
   * which sends the mesh to the other ranks. Throws (on every rank) with a
   * message if the polygons are not periodic on the box (the sides do not
   * match) or Gmsh fails.
   */
  void
  periodic_phase_mesh(
    const std::vector<std::pair<std::vector<dealii::Point<2>>, unsigned int>>
                                &polygons,
    const dealii::Point<2>      &box,
    const double                 size,
    dealii::Triangulation<2, 2> &tria,
    const MPI_Comm               comm = MPI_COMM_SELF);
} // namespace forma

#endif
