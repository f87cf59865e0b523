#ifndef forma_rhombic_tiling_h
#define forma_rhombic_tiling_h

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include <forma/microstructure/rhombic_structure.h>

#include <array>
#include <functional>
#include <vector>

namespace forma
{
  namespace rhombic
  {
    /// A quad's vertices in deal.II's order (v0, v1, v2, v3 at the
    /// reference corners (0,0), (1,0), (0,1), (1,1)).
    using Quad = std::array<dealii::Point<2>, 4>;

    Quad
    quad_of_cell(const dealii::Triangulation<2, 2>::active_cell_iterator &cell);

    /// The quads of a mesh by active cell index.
    std::vector<Quad>
    quads_of(const dealii::Triangulation<2, 2> &tria);

    /// The bilinear map of a quad at the reference point (s, t).
    dealii::Point<2>
    bilinear(const Quad &quad, const double s, const double t);

    /// Every quad split into n x n quads along the iso-lines of its
    /// bilinear map (straight, so the children tile it exactly), in the
    /// parent's orientation; `parent` gets each child's quad index.
    std::vector<Quad>
    subdivide(const std::vector<Quad>   &quads,
              const unsigned int         n,
              std::vector<unsigned int> &parent);

    /// The quad renumbered so that its fitted rhombus's acute angle is at
    /// vertex 0, where the family's cell has alpha (orientation kept).
    Quad
    acute_first(const Quad &quad);

    /// xi with x = the bilinear map of `quad` at xi (Newton from the
    /// center); true if xi lies in [0, 1]^2. Near the quad, xi is the
    /// extended map's preimage either way.
    bool
    reference_point(const Quad             &quad,
                    const dealii::Point<2> &x,
                    dealii::Point<2>       &xi);

    /**
     * Structures tiled onto quads as one level set, negative in the
     * material (thesis ch. 4.8): in each quad its structure, mapped by the
     * bilinear map from the reference cell with the acute angle first and
     * clipped to the quad,
     *   phi(x) = min_c max(l_c phi_c(xi_c(x)), s_c(x)),
     * with s_c the signed distance to quad c (the largest over its edges)
     * and l_c its half size (phi_c lives on the reference cell of side 2).
     * Neighbouring structures need not match at a shared side; this form
     * stays continuous there, which the contour tracing needs. With a
     * nonzero `period` the quads tile a periodic box [0, period] and their
     * copies shifted by one period count too, so that phi is periodic.
     * Cells are found through a bucket grid of their bounding boxes.
     *
     * Neighbouring cells share the joints at their common side's midpoint.
     * Where their joint radii p5 differ, `merge_joints` gives both the
     * average (in physical units) instead of leaving the larger one to
     * win (thesis ch. 4.8, merge error). `orient` = false takes the quads
     * as they are instead of acute_first() (e.g. children of oriented
     * quads, which must all keep their parent's orientation).
     */
    class TiledObject
    {
    public:
      TiledObject(const std::vector<Quad>             &quads,
                  const std::vector<RhombicStructure> &structures,
                  const dealii::Tensor<1, 2>          &period       = {},
                  const bool                           merge_joints = false,
                  const bool                           orient       = true);

      /// The largest difference of the joint radii (physical, over the
      /// cells' mean half size: p5 units) between two cells sharing a side,
      /// what a merge averages away.
      double largest_joint_mismatch = 0;

      double
      operator()(const dealii::Point<2> &x) const;

      /// Bounding box of the quads (without the periodic copies).
      dealii::Point<2> lo, hi;

    private:
      unsigned int
      bucket(const unsigned int d, const double v) const;

      std::vector<Quad>                                            quads;
      std::vector<std::function<double(const dealii::Point<2> &)>> phi;
      std::vector<double>                                          half_size;
      dealii::Point<2>                       box_lo, box_hi;
      double                                 pad = 0;
      std::array<unsigned int, 2>            nb;
      std::vector<std::vector<unsigned int>> buckets;
    };
  } // namespace rhombic
} // namespace forma

#endif
