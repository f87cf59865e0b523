#ifndef forma_elasticity_element_removal_h
#define forma_elasticity_element_removal_h

#include <deal.II/base/types.h>

#include <set>
#include <vector>

namespace dealii
{
  template <int dim, int spacedim>
  class Triangulation;
}

namespace forma
{
  /**
   * ESO-like element removal (thesis ch. 2.7.1, the tower crane; Huang and
   * Xie 2010): the cells to drop from a mesh whose cell stresses are low.
   *
   * `cell_stress` holds a stress measure per active cell (by active cell
   * index; every cell must be present: a serial or shared mesh). It is
   * averaged over each cell and its face neighbours (a filter: holes follow
   * the stress field, not single cells), and a cell whose filtered stress
   * is below `ratio` times the largest one is a candidate. Candidates are
   * kept if they
   * - touch a boundary with an id other than `open_id` (supports, loads,
   *   contact and interfaces stay as they are; `open_id`, the id the new
   *   holes get, is a free boundary that may be eaten into),
   * - would leave a vertex whose remaining cells are connected only
   *   through that vertex (a pinch no mesher can close), or
   * - are needed to keep a piece with a load (or another condition on a
   *   kept boundary) joined to a `holding` boundary (supports, contacts):
   *   such a piece gets its removed neighbours back, layer by layer, until
   *   it is held again; a piece with nothing but `open_id` boundary is
   *   removed whole (it would float).
   *
   * Returns the flags by active cell index.
   */
  template <int dim>
  std::vector<bool>
  select_low_stress_cells(const dealii::Triangulation<dim, dim> &tria,
                          const std::vector<double>             &cell_stress,
                          double                                 ratio,
                          dealii::types::boundary_id             open_id,
                          const std::set<dealii::types::boundary_id> &holding);
} // namespace forma

#endif
