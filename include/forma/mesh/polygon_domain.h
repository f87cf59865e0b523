#ifndef forma_mesh_polygon_domain_h
#define forma_mesh_polygon_domain_h

#include <deal.II/base/point.h>
#include <deal.II/base/types.h>

#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
}

namespace forma
{
  /// The signed area (shoelace): positive for a counter-clockwise polygon.
  double
  signed_area(const std::vector<dealii::Point<2>> &polygon);

  /**
   * A 2D domain bounded by closed polygons (outer boundaries and holes, in
   * any orientation), each side carrying a boundary id: the outline of a
   * mesh, for the operations that need the domain rather than its cells
   * (signed distance, inside test, boundary ids of another mesh of the same
   * domain).
   */
  class PolygonDomain
  {
  public:
    struct Segment
    {
      dealii::Point<2>           a, b;
      dealii::types::boundary_id id;
    };

    /// Segments that chain into closed loops (shared end points equal up
    /// to round-off); throws if a loop does not close. Telling holes from
    /// outer loops costs (loops x vertices): `classify_holes` = false
    /// skips it (Loop::hole is then false throughout).
    explicit PolygonDomain(const std::vector<Segment> &segments,
                           const bool                  classify_holes = true);

    /// The boundary faces of a 2D mesh.
    static PolygonDomain
    boundary_of(const dealii::Triangulation<2, 2> &tria,
                const bool                         classify_holes = true);

    /// Crossing-number test (even-odd over all loops).
    bool
    inside(const dealii::Point<2> &x) const;

    /// Negative inside, positive outside.
    double
    signed_distance(const dealii::Point<2> &x) const;

    /// A point `depth` inside the domain next to x's closest boundary
    /// point: moved off its side along the inward normal and towards the
    /// side's midpoint, so that it is inside at corners too. For
    /// evaluating a field of another mesh of the domain at a boundary point
    /// (each mesh's boundary is the outline only up to round-off).
    dealii::Point<2>
    point_inside_near(const dealii::Point<2> &x, const double depth) const;

    /// The id of the closest side if it is nearer than `tolerance`, else
    /// `otherwise`.
    dealii::types::boundary_id
    boundary_id(const dealii::Point<2>          &x,
                const double                     tolerance,
                const dealii::types::boundary_id otherwise) const;

    /// The loops as vertex lists, each with its sides' ids (side k joins
    /// vertex k and k + 1), and whether it bounds a hole (lies inside an
    /// odd number of other loops).
    struct Loop
    {
      std::vector<dealii::Point<2>>           vertices;
      std::vector<dealii::types::boundary_id> ids;
      bool                                    hole = false;
    };
    std::vector<Loop> loops;

    /// Bounding box.
    dealii::Point<2> lo, hi;

    /// Sum of the side lengths per boundary id.
    double
    length(const dealii::types::boundary_id id) const;

  private:
    std::vector<Segment> segments;
  };
} // namespace forma

#endif
