#ifndef forma_ipc_collision_mesh_h
#define forma_ipc_collision_mesh_h

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/types.h>

#include <forma/ipc/distance.h>

#include <array>
#include <set>
#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class DoFHandler;
  namespace hp
  {
    template <int dim, int spacedim>
    class MappingCollection;
  }
} // namespace dealii

namespace forma
{
  namespace ipc
  {
    struct ObstacleMesh;

    /**
     * The surface IPC sees (thesis ch. 3.7, Li et al. 2020): the boundary of
     * the finite element mesh as segments (2D) or triangles (3D) whose
     * vertices are the support points of the boundary faces, so that
     * higher-order elements collide on their nodes (a P2 edge gives two
     * segments, a Q2 face eight triangles). Each vertex carries the global
     * indices of its dim displacement DoFs; the displacement of a collision
     * vertex is the value of those DoFs (Lagrange elements interpolate), so
     * the map from DoFs to collision displacements is a selection, and
     * constraints (hanging nodes, Dirichlet values) act through the
     * AffineConstraints the contributions are distributed with.
     *
     * Every rank holds the whole collision mesh (gathered at construction):
     * contact couples parts owned anywhere. Vertex order follows the DoF
     * numbering.
     */
    template <int dim>
    struct CollisionMesh
    {
      /// Build from the boundary faces with ids in `boundaries` (all
      /// boundary faces if empty), at the positions of the current shape
      /// (`mapping`). With the DoF handler of the shape field (vector
      /// Lagrange elements defining `mapping`), also record how the rest
      /// positions follow the shape DoFs. Collective.
      CollisionMesh(
        const dealii::DoFHandler<dim, dim>            &dof_handler,
        const dealii::hp::MappingCollection<dim, dim> &mapping,
        const std::set<dealii::types::boundary_id>    &boundaries,
        const MPI_Comm                                 comm,
        const dealii::DoFHandler<dim, dim> *shape_dof_handler = nullptr);

      unsigned int
      n_vertices() const
      {
        return rest.size();
      }

      /// Append a static obstacle surface (vertices without DoFs) with
      /// obstacle index `id`.
      void
      add_obstacle(const ObstacleMesh &obstacle, const unsigned int id);

      /// Whether vertex v belongs to a static obstacle (no DoFs).
      bool
      fixed(const unsigned int v) const
      {
        return obstacle[v] >= 0;
      }

      /// Vertex positions at rest (the current design), z = 0 in 2D.
      std::vector<Vec> rest;
      /// Displacement DoFs of each vertex (invalid for obstacles).
      std::vector<std::array<dealii::types::global_dof_index, dim>> dofs;
      /// Material id of a cell the vertex belongs to (the body, for
      /// per-pair friction).
      std::vector<dealii::types::material_id> body;
      /// Area (2D: length) the vertex represents: half (2D) or a third (3D)
      /// of its incident segments / triangles.
      std::vector<double> vertex_area;

      /// Segments: the boundary in 2D; the triangles' edges in 3D.
      std::vector<std::array<unsigned int, 2>> edges;
      /// 3D: a third of the areas of the edge's triangles (2D: length).
      std::vector<double> edge_area;
      /// 3D: boundary triangles.
      std::vector<std::array<unsigned int, 3>> faces;

      /// Obstacle index of each vertex (-1: a vertex of the bodies).
      std::vector<int> obstacle;

      /// One term of a rest position in the shape DoFs.
      struct ShapeWeight
      {
        dealii::types::global_dof_index dof;
        unsigned int                    component;
        double                          weight;
      };
      /**
       * The upsampling M* of thesis ch. 3.7: rest[v][component] is the sum
       * of weight * (shape DoF value) over shape_weights[v] (the shape
       * field's basis at the vertex, a support point of the displacement
       * element). Empty without a shape DoF handler and for obstacles.
       */
      std::vector<std::vector<ShapeWeight>> shape_weights;

      /// Add d/d rest of sum_v s[v] vertex_area[v] to `gradient` (per
      /// vertex).
      void
      add_area_gradient(const std::vector<double> &s,
                        std::vector<Vec>          &gradient) const;

      /// All DoFs of collision vertices (every rank needs their values).
      dealii::IndexSet collision_dofs;

      /// Diagonal of the bodies' bounding box at rest.
      double
      diagonal() const;

    private:
      /// Edges of the triangles (3D) and the areas, from the primitives.
      void
      finalize();
    };
  } // namespace ipc
} // namespace forma

#endif
