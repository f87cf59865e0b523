#ifndef forma_microstructure_rhombic_structure_h
#define forma_microstructure_rhombic_structure_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <forma/microstructure/inflation_graph.h>

#include <array>
#include <functional>
#include <string>

namespace forma
{
  /**
   * The rhombic microstructure family of thesis ch. 4.4 and 4.10.1
   * (Fig. 4.3): an inflation graph with 12 nodes in a rhombic cell with the
   * rhombus's two reflection symmetries, so that every structure's
   * homogenized tensor is orthotropic with axes along the diagonals
   * (ch. 4.6.1).
   *
   * Cells. The reference cell Q is the square [0, 2]^2 (Panetta's [-1, 1]^2
   * moved to the origin, so the radii below are on the usual scale). The
   * rhombus R with the smaller angle alpha in (0, pi/2] is its image under
   * x = F x_Q, F = [a1 a2] with unit sides a1 = (cos(alpha/2), -sin(alpha/2))
   * and a2 = (cos(alpha/2), sin(alpha/2)): R has sides of length 2 and its
   * long diagonal a1 + a2 along x, so C^H in the x, y axes is orthotropic.
   * The structure is built in R (disks are round in R) and tiles R
   * periodically with period vectors 2 a1, 2 a2.
   *
   * Parameters (p1..p8 are p[0]..p[7]). With O the cell center and A, B the
   * corners at the ends of one side of Q, positions are barycentric in the
   * triangle OAB and then mapped by F:
   *  - node 1: the side midpoint (A + B) / 2, fixed: it joins the
   *    neighbouring cell, and its radius p5 is the joint's thickness;
   *  - node 2: O + p1 (A - O) + p2 (B - O), i.e. barycentric
   *    (1 - p1 - p2, p1, p2);
   *  - node 3: O + p3 (A - O), on the diagonal through A;
   *  - node 4: O + p4 (B - O), on the other diagonal;
   *  - radii p5, p6, p7, p8 of nodes 1, 2, 3, 4.
   * Edges in OAB: 1-2, 2-3, 2-4, 3-4. The two diagonal reflections give the
   * other three quarters: 12 nodes (nodes 3 and 4 lie on the mirror lines,
   * so each has 2 images) and 16 edges. Nodes 2, 3 and 4 and the 3-4 ring
   * around the center make re-entrant (auxetic) structures when node 2 lies
   * inside the ring and convex ones when it lies outside.
   *
   * Every vertex blends with the length `blending` (the thesis keeps
   * b = 0.01 fixed); see InflationGraph for the joints.
   */
  struct RhombicStructure
  {
    static constexpr unsigned int n_parameters = 8;
    static constexpr double       side         = 2;

    std::array<double, n_parameters> p = {
      {0.3, 0.3, 0.5, 0.5, 0.2, 0.12, 0.12, 0.12}};
    double alpha    = M_PI / 2;
    double blending = 0.01;

    /// The sweep ranges of thesis ch. 4.10.2: offsets p1, p2 in
    /// [0.1, 0.5], p3, p4 in [0.1, 0.9], radii in [0.05, 0.3].
    static std::array<std::array<double, 2>, n_parameters>
    ranges();

    /// What the geometry allows (check()): offsets in [0.01, 0.99], radii
    /// in [0.01, 0.6].
    static std::array<std::array<double, 2>, n_parameters>
    limits();

    /// "p1" ... "p8"
    static std::string
    parameter_name(const unsigned int i);

    /// The index of "p1" ... "p8"; anything else is an error naming the
    /// parameter-file entry it came from.
    static unsigned int
    parameter_index(const std::string &name, const std::string &entry);

    /// Throws a clear error if a parameter, alpha or the blending is out of
    /// range.
    void
    check() const;

    /// F: the reference square onto the rhombus.
    dealii::Tensor<2, 2>
    cell_map() const;

    /**
     * The level set at the cell's corner, where the four corners of the
     * reference square meet periodically: about the distance from the
     * corner to the material, +infinity where no primitive comes near it.
     * Node 4 lies on the short diagonal, which ends at the obtuse corners:
     * when its joint reaches the corner (at small angles, p4 near 0.9) it
     * joins its image in the cell across the corner, the material covers
     * the corner (a negative clearance) and the structure changes topology
     * (two more boundary loops; E nearly doubles). Node 3's joint at the
     * acute corner (p3 near 0.9 with thick struts) counts the same.
     */
    double
    corner_clearance() const;

    /// The smallest corner clearance the maps and inverse problems keep:
    /// the gap between a joint and its image across the corner (about twice
    /// the clearance) is then at least one default boundary element.
    static constexpr double min_corner_clearance = 0.00625;

    /**
     * The structure mirrored across the line through O and the midpoint of
     * AB: A and B swap, so p1 <-> p2, p3 <-> p4 and p7 <-> p8 (alpha is
     * kept). On the square cell that line is a symmetry of the cell, so
     * the mirror image is the same material mirrored: the same isotropic
     * moduli, anisotropy and volume fraction from a second branch of
     * parameters.
     */
    RhombicStructure
    mirrored() const;

    /// The parameter that mirrored() exchanges with p[i] (i itself for p5,
    /// p6).
    static unsigned int
    mirror_partner(const unsigned int i);

    /**
     * Lowers p4 (node 4 towards the center, not below `lowest`) just enough
     * that corner_clearance() >= `clearance` (to 1e-7 in p4).
     * Returns whether p4 moved; it stays where the corner is clear already
     * or where p4 = `lowest` would not clear it either.
     */
    bool
    clear_corner(const double clearance, const double lowest);

    /**
     * The periodic inflation graph in R around the cell: the cell's 12
     * nodes and 16 edges and those of the neighbouring cells whose
     * primitives reach into R. `Number` is double or Sacado::Fad::DFad<double>
     * (derivatives with respect to p). With `near` (a point of R), only the
     * primitives that can matter there: the graph for evaluating the level
     * set at that point alone, built faster (it may have no edges, and
     * its value is cut off at its own reach).
     */
    template <typename Number>
    InflationGraph<Number>
    graph(const std::array<Number, n_parameters> &parameters,
          const std::array<double, 4>            &side_radii = {},
          const dealii::Point<2>                 *near       = nullptr) const;

    /**
     * The structure's level set on the reference square (negative in the
     * material), periodic on [0, 2]^2. The graph is built once.
     *
     * `side_radii` (nonzero entries) replace p5 at the joints on the
     * midpoints of the sides y = 0, x = 2, y = 2 and x = 0 of the reference
     * square (in this order): the merge of thesis ch. 4.8, where a joint
     * shared with a neighbouring cell of another p5 gets the average. The
     * level set is then no longer periodic.
     */
    std::function<double(const dealii::Point<2> &)>
    level_set(const std::array<double, 4> &side_radii = {}) const;

    /// The 12 node positions on the reference square (for drawing).
    std::array<dealii::Point<2>, 12>
    reference_nodes() const;
  };
} // namespace forma

#endif
