#ifndef forma_mesh_mesh_h
#define forma_mesh_mesh_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <forma/mesh/pipe_graph.h>

#include <memory>
#include <string>

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
  namespace parallel
  {
    template <int dim, int spacedim>
    class TriangulationBase;
  }
} // namespace dealii

namespace forma
{
  /// The `Mesh` section shared by every app.
  struct MeshParameters
  {
    std::string  source;    ///< "generator", "file" or "pipe graph"
    std::string  generator; ///< a GridGenerator function name
    std::string  generator_arguments;
    std::string  file; ///< resolved against the .prm directory
    std::string  file_as_given;
    bool         convert_to_simplices = false;
    unsigned int initial_refinement   = 0;
    std::string  separate_interfaces; ///< see InterfaceCut
    PipeGraph    pipe_graph;          ///< for source "pipe graph"

    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(dealii::ParameterHandler &prm, const std::string &prm_directory);
  };

  /// The coarse mesh (generator, Gmsh file or pipe graph), checked for
  /// inverted cells, with the interfaces of `Separate interfaces` cut open.
  /// Collective over `comm`: a pipe graph is meshed on its root.
  template <int dim>
  void
  create_coarse_mesh(const MeshParameters            &params,
                     dealii::Triangulation<dim, dim> &tria,
                     const MPI_Comm                   comm = MPI_COMM_SELF);

  /**
   * Throws a message naming the first cell whose Jacobian is not positive at
   * a vertex (inverted or degenerate elements), with its vertices.
   */
  template <int dim>
  void
  check_mesh_validity(const dealii::Triangulation<dim, dim> &tria,
                      const std::string                     &where);

  /**
   * The distributed triangulation for the run: p4est for quads/hexes (so
   * adaptive refinement scales), a shared triangulation for simplices and
   * for meshes with separated interfaces (whose contact pairs need the
   * cells on both sides on every rank).
   */
  template <int dim>
  std::unique_ptr<dealii::parallel::TriangulationBase<dim, dim>>
  create_distributed_mesh(const MeshParameters &params, const MPI_Comm comm);

  /// An empty triangulation of the kind create_distributed_mesh() picks:
  /// shared for simplices or when `shared` (cut interfaces), else p4est.
  template <int dim>
  std::unique_ptr<dealii::parallel::TriangulationBase<dim, dim>>
  make_parallel_triangulation(const bool     simplex,
                              const bool     shared,
                              const MPI_Comm comm);
} // namespace forma

#endif
