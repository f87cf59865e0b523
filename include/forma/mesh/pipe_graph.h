#ifndef forma_mesh_pipe_graph_h
#define forma_mesh_pipe_graph_h

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>

#include <string>
#include <vector>

namespace forma
{
  /**
   * A pipe assembly from a graph (thesis ch. 2.7, "3D pipe-like": tent, truss,
   * dodecahedron; the coat rack's dowels and connectors): every node becomes
   * a ball connector (material 1 unless given), every edge a pipe (material
   * 2 unless given) whose ends sit in sockets of its balls. A free end is a
   * node without a ball: its one pipe runs to the node and ends flat there.
   * The parts share their socket surfaces (a conforming tetrahedral mesh),
   * so `Mesh/Separate interfaces = 1-2 : id` cuts every contact between
   * materials 1 and 2 at once, and parts of one material, or of a pair not
   * separated, stay glued (a PLA hook arm on its connector). Clip planes
   * cut the assembly (a
   * floor for rigid contact, a flat pad to load, the mirror planes of a
   * symmetric assembly).
   */
  struct PipeGraph
  {
    struct Node
    {
      dealii::Point<3> x;
      /// The ball's free surface, or a free end's flat face.
      unsigned int boundary_id;
      unsigned int material = 1;
      bool         free_end = false; ///< no ball: one pipe ends here
    };
    struct Edge
    {
      unsigned int a, b;
      unsigned int boundary_id; ///< the pipe's free surface
      unsigned int material = 2;
    };
    /// Keep the side normal . x >= offset (normal of unit length); the cut
    /// faces get `boundary_id`.
    struct Clip
    {
      dealii::Tensor<1, 3> normal;
      double               offset;
      unsigned int         boundary_id;
    };

    std::vector<Node> nodes;
    std::vector<Edge> edges;
    std::vector<Clip> clips;
    double            connector_radius = 0;
    double            pipe_radius      = 0;
    /// How far a pipe reaches into a ball, from the ball's surface along
    /// the pipe's axis: the pipe ends at connector_radius - socket_depth
    /// from the node.
    double       socket_depth        = 0;
    double       mesh_size           = 0;
    unsigned int elements_per_circle = 12; ///< curvature sizing

    /// The `Pipe graph` subsection (inside `Mesh`).
    static void
    declare(dealii::ParameterHandler &prm);
    /// Read and check the subsection (inside `Mesh`).
    void
    parse(dealii::ParameterHandler &prm);

    /// Throws a message naming the nodes or edges when parts would overlap:
    /// balls closer than their diameter, sockets of one ball that meet,
    /// pipes that cross or pass through a ball, a socket that does not
    /// open to the ball's surface; or when a free end has other than one
    /// pipe, or a pipe would be too short to leave its balls.
    void
    check() const;

  private:
    void
    check_sizes() const;
    void
    check_edges() const;
    void
    check_balls() const;
    void
    check_pipes() const;
    void
    check_sockets() const;
  };

  /// The assembly meshed with tetrahedra by Gmsh (OpenCASCADE), as Gmsh 2.2
  /// text: physical volumes the nodes' and edges' materials, physical
  /// surfaces the nodes', edges' and clip planes' boundary ids (0: left
  /// untagged).
  /// Collective over `comm`: meshed on its root, the text (or the root's
  /// error) sent to every rank.
  std::string
  pipe_graph_mesh(const PipeGraph &graph, const MPI_Comm comm = MPI_COMM_SELF);
} // namespace forma

#endif
