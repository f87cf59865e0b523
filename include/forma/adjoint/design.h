#ifndef forma_adjoint_design_h
#define forma_adjoint_design_h

#include <deal.II/base/parameter_handler.h>

#include <string>
#include <vector>

namespace forma
{
  /**
   * Which physical parameters form the design vector q of thesis eq. 3.3
   * (the `Design` section), and how shape parameters are constrained.
   *
   * Blocks, in this order when selected:
   * - `shape`: displacement of the vertices of the shape field (thesis ch.
   *   3.7.1) from the mesh as read, one entry per shape DoF. Vertices on
   *   `Fixed boundaries` do not move, vertices on a symmetry plane keep
   *   their normal coordinate, hanging vertices follow their parents.
   *   With `Shape parameterization = boundary`, only the boundary entries
   *   are design variables: interior vertices follow by harmonic extension
   *   (a Laplace problem on the mesh as read), which keeps the interior
   *   mesh smooth as the boundary moves; interior entries are ignored and
   *   get zero gradient.
   * - `cell material`: (lambda, mu) or (E, nu) per active cell.
   * - `material`: (lambda, mu) or (E, nu) per material id.
   * - `damping`: (shear, bulk) damping coefficients per material id.
   * - `friction`: the IPC friction coefficients (thesis ch. 3.7, one per
   *   pair of bodies): IPC/Friction coefficient, each Friction pairs
   *   record, each obstacle with its own coefficient.
   * - `loads`: a scale factor per traction record, then one for the body
   *   force and one for gravity (only those the problem has).
   * - `initial displacement`, `initial velocity`: a uniform vector added to
   *   the initial condition (thesis ch. 3.5.3); `initial displacement per
   *   body`, `initial velocity per body`: a vector per material id of
   *   `Bodies` (all if empty) added on that body (a throw); `initial
   *   displacement
   *   field`, `initial velocity field`: a value per displacement DoF added
   *   to it.
   */
  struct DesignParameters
  {
    std::vector<std::string> blocks;
    bool                     young_poisson = true; ///< (E, nu), else Lame
    std::string              fixed_boundaries;
    std::string              fixed_bodies; ///< material ids, comma-separated
    std::string              symmetry_planes;
    std::string              shape_perturbation;
    double                   min_scaled_jacobian = 1e-3;
    /// Check min_scaled_jacobian at the cells' corners too (quad/hex).
    bool        check_corners = true;
    double      shape_bound   = 0;      ///< 0: free
    std::string start;                  ///< starting block values (records)
    std::string bodies;                 ///< material ids of per-body blocks
    bool        boundary_shape = false; ///< see below
    /// Remeshing resamples the free boundary curves (2D), see
    /// resample_boundaries(); else it keeps every boundary facet.
    bool   resample_boundary    = false;
    double remesh_boundary_size = 0;  ///< 0: the current local size
    double remesh_feature_angle = 30; ///< degrees
    /// Radius of the shape filter (ShapeFilter); 0: none.
    double shape_filter_radius = 0;

    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(dealii::ParameterHandler &prm);

    bool
    has(const std::string &block) const;
  };

  /// One named block of a design vector.
  struct DesignBlock
  {
    std::string  name;
    unsigned int offset;
    unsigned int size;
    /// Whether the block lives on the mesh (per cell, per DoF): it cannot
    /// be carried over a remesh.
    bool on_mesh = false;
    /// How reports summarize the block's values.
    enum class Summary
    {
      values,       ///< the values (max |value| for long blocks)
      max_change,   ///< the largest change from the start
      vertex_offset ///< the largest vertex move from the mesh as read
    };
    Summary summary = Summary::values;
    /// Entries per active cell of a block per cell (cell material), which a
    /// refinement carries over (children take their cell's); 0 otherwise.
    unsigned int per_cell = 0;
  };

  /// Layout of a design vector: its blocks in order. Every rank holds the
  /// whole vector (design vectors are small next to the state).
  struct DesignLayout
  {
    std::vector<DesignBlock> blocks;

    unsigned int
    size() const;

    /// The block called `name`, or nullptr.
    const DesignBlock *
    find(const std::string &name) const;
  };
} // namespace forma

#endif
