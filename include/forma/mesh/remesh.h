#ifndef forma_mesh_remesh_h
#define forma_mesh_remesh_h

#include <deal.II/base/point.h>
#include <deal.II/base/types.h>

#include <array>
#include <string>
#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
}

namespace forma
{
  /**
   * The boundaries of the regions of a mesh in its current shape: the
   * domain boundary and the interfaces between material ids, as segments
   * (2D) or triangles (3D). A facet is oriented with its normal pointing
   * out of the region `inside` (counterclockwise around it in 2D).
   */
  template <int dim>
  struct RegionBoundaries
  {
    struct Facet
    {
      std::array<unsigned int, dim> vertices;
      dealii::types::material_id    inside;
      /// The material on the other side, or invalid_material_id.
      dealii::types::material_id outside;
      /// Boundary id of a domain-boundary facet.
      dealii::types::boundary_id boundary_id;
    };

    std::vector<dealii::Point<dim>> vertices;
    std::vector<Facet>              facets;
  };

  /**
   * Mesh the regions enclosed by `boundaries` with Gmsh, keeping every
   * boundary and interface facet as it is (so the geometry and the
   * boundary resolution do not change; interior sizes follow the boundary):
   * triangles or tetrahedra, or (2D, `quads`) quadrilaterals by Blossom
   * recombination, which needs an even number of boundary segments per
   * region, as every region of a quad mesh has. Regions keep their
   * material ids, boundary facets their boundary ids.
   *
   * Returns the mesh as a Gmsh 2.2 ASCII file (what GridIn reads on every
   * rank); throws with a message if Gmsh fails or cannot close a region.
   */
  template <int dim>
  std::string
  mesh_regions(const RegionBoundaries<dim> &boundaries, const bool quads);

  /// Read a mesh written by mesh_regions() into `tria` (serial).
  template <int dim>
  void
  read_regions_mesh(const std::string               &msh,
                    dealii::Triangulation<dim, dim> &tria);
} // namespace forma

#endif
