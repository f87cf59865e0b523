#ifndef forma_mesh_quad_mesh_h
#define forma_mesh_quad_mesh_h

#include <string>

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
}

namespace forma
{
  /**
   * An all-quadrilateral mesh of the 2D Gmsh geometry `geo_file` (Gmsh's
   * Frontal-Delaunay for quads with Blossom recombination, element edges
   * of about `element_size`; if triangles remain, every element is split
   * into quads at twice the size). Physical Curves give boundary ids,
   * Physical Surfaces material ids; the geometry needs at least one
   * Physical Surface. Errors name the file.
   */
  void
  gmsh_quad_mesh(const std::string           &geo_file,
                 const double                 element_size,
                 dealii::Triangulation<2, 2> &tria);
} // namespace forma

#endif
