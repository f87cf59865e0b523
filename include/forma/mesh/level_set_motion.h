#ifndef forma_mesh_level_set_motion_h
#define forma_mesh_level_set_motion_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <functional>
#include <memory>
#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
}

namespace forma
{
  /**
   * How a mesh of a level set's material (periodic_level_set_mesh) moves
   * when the level set changes and the topology is kept: the discrete
   * design-to-mesh map behind shape derivatives and their Taylor tests.
   *
   *  - Contour vertices (on phi = 0 inside the box) move along the level
   *    set's normal at the start; where the contour meets a side of the box
   *    they slide along the side, so periodic partners move alike.
   *  - Other vertices on the sides stay; the interior follows by harmonic
   *    extension (HarmonicExtension, the one the elasticity shape designs
   *    use).
   *
   * velocities() is the derivative of moved_vertices() at the start, so a
   * Taylor test of C^H(moved mesh) against the shape gradient checks both.
   */
  class LevelSetMeshMotion
  {
  public:
    /// `phi` is the level set the mesh was made from (periodic on box).
    LevelSetMeshMotion(
      const dealii::Triangulation<2, 2>                     &tria,
      const dealii::Point<2>                                &box,
      const std::function<double(const dealii::Point<2> &)> &phi);
    ~LevelSetMeshMotion();

    /**
     * Vertex velocities (indexed like the triangulation's vertices) for
     * each design variable q_i, given the level set's derivatives
     * dphi/dq_i at a point: a contour vertex keeps phi = 0 to first order.
     */
    std::vector<std::vector<dealii::Tensor<1, 2>>>
    velocities(
      const std::function<std::vector<double>(const dealii::Point<2> &)>
                        &dphi_dq,
      const unsigned int n_variables) const;

    /// Vertex positions for a new level set near the original one: each
    /// contour vertex solves new_phi = 0 along its direction.
    std::vector<dealii::Point<2>>
    moved_vertices(
      const std::function<double(const dealii::Point<2> &)> &new_phi) const;

    /// Replace `tria`'s vertex positions (a copy of the original mesh).
    static void
    set_vertices(dealii::Triangulation<2, 2>         &tria,
                 const std::vector<dealii::Point<2>> &vertices);

    /// Number of contour vertices that move (for reports).
    unsigned int
    n_moving_vertices() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl;
  };
} // namespace forma

#endif
