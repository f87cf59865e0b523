#ifndef forma_rhombic_grid_growth_h
#define forma_rhombic_grid_growth_h

#include <forma/microstructure/rhombic_structure.h>

#include <array>
#include <utility>
#include <vector>

namespace forma
{
  namespace rhombic
  {
    /**
     * The map construction's growth over one angle's (E, nu) grid (thesis
     * ch. 4.6.3, step 2 in doc/rhombic.md): an unsolved node next to solved
     * ones starts from the mean of its solved neighbours' structures. A node
     * whose solve failed is tried again once it has more solved neighbours
     * than at its last try, a start it has not had: single solves that stop
     * short would otherwise leave holes inside the coverage and cut the
     * inscribed polygon D(alpha). Each node is tried at most once per
     * neighbour count (after its seed or previous-angle start, 1 to 4), so
     * the growth always ends.
     *
     * Node n is (E_i, nu_j) with n = i n_nu + j.
     */
    class GridGrowth
    {
    public:
      using Parameters = std::array<double, RhombicStructure::n_parameters>;
      using Start      = std::pair<unsigned int, Parameters>;

      GridGrowth(const unsigned int n_E, const unsigned int n_nu);

      /// A solve of `node` (after any start: the seed, its previous
      /// angle's structure or one of next_starts()). After a start that is
      /// not a neighbours' mean, any later start from solved neighbours is
      /// new.
      void
      tried(const unsigned int node);

      /// `node` reached its target with structure `p`.
      void
      reached(const unsigned int node, const Parameters &p);

      /// The starts of the next round: every unsolved node with more solved
      /// neighbours than at its last try, from their mean. Marks them tried;
      /// empty when the growth has ended.
      std::vector<Start>
      next_starts();

      const std::vector<bool> &
      solved() const
      {
        return is_solved;
      }

      unsigned int
      n_solved() const;

      /// The reached structures (zero where a node is unsolved).
      const std::vector<Parameters> &
      structures() const
      {
        return structure;
      }

    private:
      const unsigned int      n_E, n_nu;
      std::vector<bool>       is_solved;
      std::vector<Parameters> structure;
      // Solved neighbours at the last try: -1 never tried, 0 tried from a
      // start that was not a neighbours' mean.
      std::vector<int> neighbours_at_try;
    };
  } // namespace rhombic
} // namespace forma

#endif
