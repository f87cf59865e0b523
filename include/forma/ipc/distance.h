#ifndef forma_ipc_distance_h
#define forma_ipc_distance_h

#include <deal.II/base/tensor.h>

#include <array>
#include <vector>

namespace dealii
{
  template <typename number>
  class FullMatrix;
}

namespace forma
{
  namespace ipc
  {
    /// Positions in space; 2D problems use z = 0.
    using Vec = dealii::Tensor<1, 3>;

    /**
     * The smooth distance formulas IPC evaluates once a primitive pair is
     * classified (Li et al. 2020, sec. 4.1), as squared distances:
     *  - point_point (p, q): |p - q|^2
     *  - point_edge (p, a, b): distance of p to the line through a, b
     *  - point_triangle (p, a, b, c): distance of p to the plane of a, b, c
     *  - edge_edge (a0, a1, b0, b1): distance between the two lines
     *  - point_plane (p, o, n): ((p - o) . n)^2 for a unit normal n
     * Each is smooth where it applies; which one applies is the pair's
     * distance type.
     */
    enum class DistanceType : unsigned char
    {
      point_point,
      point_edge,
      point_triangle,
      edge_edge,
      point_plane
    };

    /// Number of arguments of a formula.
    unsigned int
    n_arguments(const DistanceType type);

    /**
     * A classified pair: the formula that gives its distance and which of
     * the pair's vertices it reads (argument k is vertex slot[k] of the
     * pair), with the squared distance at the classified positions.
     */
    struct DistanceStencil
    {
      DistanceType                 type = DistanceType::point_point;
      std::array<unsigned char, 4> slot{{0, 1, 2, 3}};
      double                       distance_squared = 0;
    };

    /// Point p against the segment [a, b]; pair vertices (p, a, b).
    DistanceStencil
    classify_point_edge(const Vec &p, const Vec &a, const Vec &b);

    /// Point p against the triangle (a, b, c); pair vertices (p, a, b, c).
    DistanceStencil
    classify_point_triangle(const Vec &p,
                            const Vec &a,
                            const Vec &b,
                            const Vec &c);

    /// Segment [a0, a1] against [b0, b1] in 3D; pair vertices
    /// (a0, a1, b0, b1). Nearly parallel segments use their end points.
    DistanceStencil
    classify_edge_edge(const Vec &a0,
                       const Vec &a1,
                       const Vec &b0,
                       const Vec &b1);

    /**
     * The squared distance of a formula at its arguments `x`, and, when
     * asked, its gradient (3 entries per argument) and Hessian with respect
     * to the arguments' coordinates (forward AD).
     */
    double
    distance_squared(const DistanceType          type,
                     const std::vector<Vec>     &x,
                     std::vector<double>        *gradient = nullptr,
                     dealii::FullMatrix<double> *hessian  = nullptr);
  } // namespace ipc
} // namespace forma

#endif
