#ifndef forma_microstructure_inflation_graph_h
#define forma_microstructure_inflation_graph_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>

#include <array>
#include <limits>
#include <vector>

namespace forma
{
  /**
   * The 2D inflation graph geometry of thesis ch. 4.10.1 (after Panetta
   * et al. 2017): a graph whose vertices carry a position, a radius and a
   * blending length, inflated into the zero sublevel set of
   *
   *  - an edge primitive per edge: the convex hull of the two vertex disks
   *    (two disks joined by their outer common tangents), with its exact
   *    signed distance d_e;
   *  - a joint per vertex: the smooth minimum (eq. 4.17)
   *      J_i = KS(d_e : e at i) = -s_i ln sum_e exp(-d_e / s_i)
   *    of its edges, with s_i = b_i * m_i the vertex blending length b_i
   *    modulated by the joint's smallest incident angle theta_i:
   *    m_i = (pi/2) / theta_i clamped to [1, 3], so acute joints get wider
   *    fillets;
   *  - joint-to-joint blending: the two lowest joints J_a <= J_b are merged
   *    by a polynomial smooth minimum whose width is 2 (min_e d_e - J_a), the
   *    amount joint a is already smoothed there. Along an edge, away from
   *    the joints' fillets, both joints equal d_e and the union is exact
   *    (no swelling of the edges); near a fillet the crease where two
   *    joints' level sets meet is rounded.
   *
   * The value is negative inside the material. It is a signed distance
   * away from the fillets (up to a cut-off far outside the material) and
   * Lipschitz everywhere. `Number` is double or a
   * Sacado forward AD type (derivatives with respect to vertex data, e.g.
   * shape parameters); positions passed to value() are plain points.
   */
  template <typename Number>
  class InflationGraph
  {
  public:
    /// The largest joint modulation m_i.
    static constexpr double max_modulation = 3;

    struct Vertex
    {
      std::array<Number, 2> position;
      Number                radius;
      double                blending = 0.01;
    };

    /// Edges by vertex index. Joint modulation uses the incident angles.
    InflationGraph(const std::vector<Vertex>                      &vertices,
                   const std::vector<std::array<unsigned int, 2>> &edges);

    Number
    value(const dealii::Point<2> &x) const;

    /// Signed distance to one edge primitive.
    Number
    edge_distance(const unsigned int e, const dealii::Point<2> &x) const;

    /// Bounding box (lower, upper corner) of the inflated graph, padded by
    /// the largest fillet.
    std::array<dealii::Point<2>, 2>
    bounding_box() const;

    unsigned int
    n_edges() const
    {
      return edges.size();
    }

    /// value() never exceeds this: beyond the fillets' reach the level set
    /// is cut off (see `reach`); +infinity for a graph without edges.
    double
    max_value() const
    {
      return edges.empty() ? std::numeric_limits<double>::infinity() : reach;
    }

  private:
    std::vector<Vertex>                      vertices;
    std::vector<std::array<unsigned int, 2>> edges;
    /// Per vertex: incident edges and the modulated blending length.
    std::vector<std::vector<unsigned int>> incident;
    std::vector<Number>                    joint_blending;
    /**
     * Buckets of a uniform grid over the bounding box, each listing the
     * edges within `reach` of it. Farther edges change the value by less
     * than exp(-reach / blending) (negligible) unless the value exceeds
     * `reach`, so value() is min(value, reach), the same from every bucket.
     */
    double                                 reach = 0;
    std::array<dealii::Point<2>, 2>        box;
    std::array<unsigned int, 2>            n_buckets;
    std::vector<std::vector<unsigned int>> bucket_edges;
    std::vector<std::vector<unsigned int>> bucket_joints;
  };
} // namespace forma

#endif
