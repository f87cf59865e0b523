#include <deal.II/base/exceptions.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <forma/elasticity/element_removal.h>

#include <algorithm>
#include <set>

namespace forma
{
  using namespace dealii;

  namespace
  {
    /**
     * select_low_stress_cells()'s state: which cells must stay (anchored:
     * on a support, a contact or a glued interface; held: on a boundary of
     * `holding`), and which are removed.
     */
    template <int dim>
    class LowStressSelection
    {
    public:
      using cell_iterator = typename Triangulation<dim>::active_cell_iterator;

      /// The cells whose filtered stress (their own and their neighbours'
      /// mean) is below ratio times its maximum, anchored ones excepted.
      LowStressSelection(const Triangulation<dim, dim>      &tria,
                         const std::vector<double>          &cell_stress,
                         const double                        ratio,
                         const types::boundary_id            open_id,
                         const std::set<types::boundary_id> &holding);

      /// Pinches: removal must not split the kept cells around a vertex
      /// into more fans than the mesh has there; otherwise the removed
      /// cells there come back. Returns whether any did.
      bool
      restore_pinches();

      /**
       * Pieces: one that touches a support or contact stays; one that
       * touches only the open boundary would float and goes whole; one
       * that carries a load or another condition but is cut off from every
       * support gets its removed neighbours back (layer by layer it joins
       * its part again). Returns whether any came back.
       */
      bool
      settle_pieces();

      std::vector<bool> remove;

    private:
      /// Face-connected fans of the given cells around one vertex.
      static unsigned int
      count_fans(const std::vector<cell_iterator> &cells);

      const Triangulation<dim, dim>       &tria;
      std::vector<bool>                    anchored, held;
      std::vector<std::set<cell_iterator>> vertex_cells;
      /// A vertex can join cells through itself alone in the mesh as given
      /// (where a cut interface ends): only fans the removal adds are
      /// pinches.
      std::vector<unsigned int> fans_as_given;
    };



    template <int dim>
    LowStressSelection<dim>::LowStressSelection(
      const Triangulation<dim, dim>      &tria,
      const std::vector<double>          &cell_stress,
      const double                        ratio,
      const types::boundary_id            open_id,
      const std::set<types::boundary_id> &holding)
      : remove(tria.n_active_cells(), false)
      , tria(tria)
      , anchored(tria.n_active_cells(), false)
      , held(tria.n_active_cells(), false)
      , vertex_cells(GridTools::vertex_to_cell_map(tria))
    {
      const unsigned int  n = tria.n_active_cells();
      std::vector<double> filtered(n, 0.);
      double              max_filtered = 0;
      for (const auto &cell : tria.active_cell_iterators())
        {
          const unsigned int c     = cell->active_cell_index();
          double             sum   = cell_stress[c];
          unsigned int       count = 1;
          for (const auto f : cell->face_indices())
            if (cell->at_boundary(f))
              {
                const auto id = cell->face(f)->boundary_id();
                anchored[c]   = anchored[c] || id != open_id;
                held[c]       = held[c] || holding.count(id) > 0;
              }
            else
              {
                // A glued (uncut) interface between materials stays too.
                anchored[c] = anchored[c] || cell->neighbor(f)->material_id() !=
                                               cell->material_id();
                sum += cell_stress[cell->neighbor(f)->active_cell_index()];
                ++count;
              }
          filtered[c]  = sum / count;
          max_filtered = std::max(max_filtered, filtered[c]);
        }
      for (unsigned int c = 0; c < n; ++c)
        remove[c] = !anchored[c] && filtered[c] < ratio * max_filtered;
      fans_as_given.resize(vertex_cells.size());
      for (unsigned int v = 0; v < vertex_cells.size(); ++v)
        fans_as_given[v] =
          count_fans(std::vector<cell_iterator>(vertex_cells[v].begin(),
                                                vertex_cells[v].end()));
    }



    template <int dim>
    unsigned int
    LowStressSelection<dim>::count_fans(const std::vector<cell_iterator> &cells)
    {
      std::vector<bool> reached(cells.size(), false);
      unsigned int      fans = 0;
      for (unsigned int s = 0; s < cells.size(); ++s)
        {
          if (reached[s])
            continue;
          ++fans;
          std::vector<unsigned int> stack = {s};
          reached[s]                      = true;
          while (!stack.empty())
            {
              const auto a = cells[stack.back()];
              stack.pop_back();
              for (unsigned int k = 0; k < cells.size(); ++k)
                if (!reached[k])
                  for (const auto f : a->face_indices())
                    if (!a->at_boundary(f) && a->neighbor(f) == cells[k])
                      {
                        reached[k] = true;
                        stack.push_back(k);
                        break;
                      }
            }
        }
      return fans;
    }



    template <int dim>
    bool
    LowStressSelection<dim>::restore_pinches()
    {
      bool restored = false;
      for (unsigned int v = 0; v < vertex_cells.size(); ++v)
        {
          std::vector<cell_iterator> kept;
          bool                       any_removed = false;
          for (const auto &cell : vertex_cells[v])
            if (remove[cell->active_cell_index()])
              any_removed = true;
            else
              kept.push_back(cell);
          if (!any_removed || kept.size() < 2 ||
              count_fans(kept) <= fans_as_given[v])
            continue;
          for (const auto &cell : vertex_cells[v])
            remove[cell->active_cell_index()] = false;
          restored = true;
        }
      return restored;
    }



    template <int dim>
    bool
    LowStressSelection<dim>::settle_pieces()
    {
      std::vector<int>          piece(tria.n_active_cells(), -1);
      std::vector<unsigned int> drop, back;
      for (const auto &seed : tria.active_cell_iterators())
        {
          if (remove[seed->active_cell_index()] ||
              piece[seed->active_cell_index()] >= 0)
            continue;
          const int                  id      = seed->active_cell_index();
          std::vector<cell_iterator> members = {seed}, stack = {seed};
          piece[id]    = id;
          bool is_held = false, is_anchored = false;
          while (!stack.empty())
            {
              const auto cell = stack.back();
              stack.pop_back();
              is_held     = is_held || held[cell->active_cell_index()];
              is_anchored = is_anchored || anchored[cell->active_cell_index()];
              for (const auto f : cell->face_indices())
                if (!cell->at_boundary(f))
                  {
                    const auto nb = cell->neighbor(f);
                    const auto k  = nb->active_cell_index();
                    if (!remove[k] && piece[k] < 0)
                      {
                        piece[k] = id;
                        stack.push_back(nb);
                        members.push_back(nb);
                      }
                  }
            }
          if (is_held)
            continue;
          for (const auto &cell : members)
            if (!is_anchored)
              drop.push_back(cell->active_cell_index());
            else
              for (const auto f : cell->face_indices())
                if (!cell->at_boundary(f) &&
                    remove[cell->neighbor(f)->active_cell_index()])
                  back.push_back(cell->neighbor(f)->active_cell_index());
        }
      // Applied after the pass: the flood above reads one state.
      for (const auto c : drop)
        remove[c] = true;
      for (const auto c : back)
        remove[c] = false;
      return !back.empty();
    }
  } // namespace



  template <int dim>
  std::vector<bool>
  select_low_stress_cells(const Triangulation<dim, dim>      &tria,
                          const std::vector<double>          &cell_stress,
                          const double                        ratio,
                          const types::boundary_id            open_id,
                          const std::set<types::boundary_id> &holding)
  {
    const unsigned int n = tria.n_active_cells();
    AssertThrow(cell_stress.size() == n,
                ExcMessage("element removal: one stress value per cell is "
                           "needed (" +
                           std::to_string(cell_stress.size()) + " for " +
                           std::to_string(n) + " cells)."));
    AssertThrow(ratio > 0 && ratio < 1,
                ExcMessage("element removal: the stress ratio must lie in "
                           "(0, 1)."));
    LowStressSelection<dim> s(tria, cell_stress, ratio, open_id, holding);
    // Restoring joins fans and pieces; a restored cell joins a piece that
    // is held or anchored and stays. The cap guards against a cycle.
    unsigned int rounds = 0;
    for (bool changed = true; changed; ++rounds)
      {
        AssertThrow(rounds < n + 2,
                    ExcMessage("element removal: the choice of cells does "
                               "not settle."));
        changed = s.restore_pinches();
        changed = s.settle_pieces() || changed;
      }
    return s.remove;
  }

  template std::vector<bool>
  select_low_stress_cells(const Triangulation<2, 2> &,
                          const std::vector<double> &,
                          double,
                          types::boundary_id,
                          const std::set<types::boundary_id> &);
  template std::vector<bool>
  select_low_stress_cells(const Triangulation<3, 3> &,
                          const std::vector<double> &,
                          double,
                          types::boundary_id,
                          const std::set<types::boundary_id> &);
} // namespace forma
