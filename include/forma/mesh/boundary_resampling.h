#ifndef forma_mesh_boundary_resampling_h
#define forma_mesh_boundary_resampling_h

#include <forma/mesh/remesh.h>

#include <set>

namespace forma
{
  /**
   * How resample_boundaries() places the new boundary vertices.
   */
  struct BoundaryResampling
  {
    /// Target segment length; 0: the current local length, smoothed along
    /// each piece (so the count stays about the same and the spacing
    /// becomes even); in 3D, the mean edge length of the free patches.
    double size = 0;
    /// A vertex where the boundary turns by more than this (radians) is a
    /// corner and stays; in 3D, an edge where the surface bends by more.
    double feature_angle = 0.5;
    /// Largest turn (radians) of the resampled curve over one segment: a
    /// bend keeps as many vertices as it needs (2D).
    double max_turn = 0.2;
    /// Largest relative change of any region's area (2D) or volume (3D)
    /// before the result is refused.
    double max_area_change = 1e-3;
    /// Boundary ids and material ids whose facets stay as they are (fixed
    /// boundaries and fixed parts keep their vertices).
    std::set<dealii::types::boundary_id> kept_boundaries;
    std::set<dealii::types::material_id> kept_materials;

    /// Whether a facet with these ids stays as it is.
    bool
    keeps(const dealii::types::material_id inside,
          const dealii::types::material_id outside,
          const dealii::types::boundary_id boundary) const;
  };

  /**
   * The region boundaries of a 2D mesh with every free piece resampled:
   * the facets of one key (inside, outside material, boundary id) form
   * chains; corners (where keys meet, where the curve turns by more than
   * the feature angle, and every vertex of a kept facet) stay, and the
   * vertices between two corners are placed anew along the polyline
   * through the old ones, evenly in the size function, then moved off it
   * (by a fraction of the sagitta) so that each piece encloses the area it
   * did: the regions keep their areas to round-off and second order. The two
   * sides of a cut interface (two keys, coincident vertices) are
   * resampled identically, so the new mesh keeps them coincident.
   *
   * Throws if a region's area changes by more than max_area_change.
   */
  RegionBoundaries<2>
  resample_boundaries(const RegionBoundaries<2> &boundaries,
                      const BoundaryResampling  &options);

  /// The area of every region (material id) enclosed by `boundaries`.
  std::map<dealii::types::material_id, double>
  region_areas(const RegionBoundaries<2> &boundaries);

  /**
   * The region boundaries of a 3D mesh with every free surface patch (the
   * facets of one key connected through edges) remeshed isotropically by
   * CGAL (Polygon Mesh Processing) at the target size, on its current
   * shape. Patch borders (where keys meet, so ids and interfaces keep
   * their extent) keep their vertices, and so do the sharp edges inside a
   * patch (where the surface bends by more than the feature angle) but for
   * a vertex between a segment shorter than 4/5 of the size and the next,
   * which is collapsed into its nearer neighbour on that edge. Those
   * edges longer than 4/3 of the size are split at their midpoints (on all
   * sides, so patches stay conforming). The free vertices of each patch
   * are then moved along the gradient of the volume it encloses, so that
   * every region keeps its volume to round-off. Kept boundaries and
   * materials keep their facets (their edges beside a free patch split at
   * midpoints), and so do patches whose every vertex has a copy at the
   * same point (a side of a cut interface; list cut interfaces' ids as
   * kept, since a cut that meets a third part shares vertices there).
   *
   * Throws if a patch is not a manifold surface, if CGAL fails, if
   * keeping a patch's volume would move a vertex by more than a quarter of
   * the size, or if a region's volume changes by more than
   * max_area_change.
   */
  RegionBoundaries<3>
  resample_boundaries(const RegionBoundaries<3> &boundaries,
                      const BoundaryResampling  &options);

  /// The volume of every region (material id) enclosed by `boundaries`.
  std::map<dealii::types::material_id, double>
  region_volumes(const RegionBoundaries<3> &boundaries);
} // namespace forma

#endif
