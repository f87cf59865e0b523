#include <deal.II/base/exceptions.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/distributed/shared_tria.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/numerics/data_out.h>

#include <forma/homogenization/periodic_homogenization.h>
#include <forma/solvers/linear_solver.h>
#include <forma/solvers/sparse_cholesky.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <tuple>

namespace forma
{
  using namespace dealii;

  namespace
  {
    // Voigt index -> tensor indices; shears carry the engineering factor.
    template <int dim>
    constexpr unsigned int n_voigt = dim *(dim + 1) / 2;

    template <int dim>
    std::pair<unsigned int, unsigned int>
    voigt_pair(const unsigned int a)
    {
      if (a < dim)
        return {a, a};
      if (dim == 2)
        return {0, 1};
      static const unsigned int i[3] = {1, 0, 0}, j[3] = {2, 2, 1};
      return {i[a - dim], j[a - dim]};
    }

    /// The unit test strain of Voigt index a (engineering shear = 1).
    template <int dim>
    SymmetricTensor<2, dim>
    test_strain(const unsigned int a)
    {
      SymmetricTensor<2, dim> A;
      const auto [i, j] = voigt_pair<dim>(a);
      A[i][j]           = (i == j) ? 1. : 0.5;
      return A;
    }

    /// Voigt vector (engineering shear) of a symmetric strain.
    template <int dim>
    void
    strain_to_voigt(const SymmetricTensor<2, dim> &e, double *v)
    {
      for (unsigned int a = 0; a < n_voigt<dim>; ++a)
        {
          const auto [i, j] = voigt_pair<dim>(a);
          v[a]              = (i == j) ? e[i][j] : 2 * e[i][j];
        }
    }
  } // namespace



  namespace
  {
    /// A point (relative to the box, to 1e-9) and a component as a map key.
    template <int dim>
    std::array<long long, dim + 1>
    position_key(const Point<dim>  &p,
                 const unsigned int c,
                 const Point<dim>  &box)
    {
      std::array<long long, dim + 1> k;
      for (unsigned int d = 0; d < dim; ++d)
        k[d] = std::llround(p[d] / (1e-9 * box[d]));
      k[dim] = c;
      return k;
    }

    /**
     * Values by point (and component), found allowing for the round-off of
     * points computed two ways (a mirror image, a mesh file): the point's
     * key or a neighbouring one. Sorted once, then searched.
     */
    template <int dim, typename T>
    class PositionIndex
    {
    public:
      using Key = std::array<long long, dim + 1>;

      explicit PositionIndex(const Point<dim> &box)
        : box(box)
      {}

      void
      insert(const Point<dim> &p, const unsigned int c, const T &value)
      {
        entries.emplace_back(position_key(p, c, box), value);
      }

      /// After the insertions; one entry per key is kept (any one: the
      /// callers insert equal values under equal keys).
      void
      sort()
      {
        const auto by_key = [](const auto &a, const auto &b) {
          return a.first < b.first;
        };
        std::sort(entries.begin(), entries.end(), by_key);
        entries.erase(std::unique(entries.begin(),
                                  entries.end(),
                                  [](const auto &a, const auto &b) {
                                    return a.first == b.first;
                                  }),
                      entries.end());
      }

      const T *
      find(const Point<dim> &p, const unsigned int c) const
      {
        const Key key = position_key(p, c, box);
        for (int n = -1; n < Utilities::pow(3, dim); ++n)
          {
            if (n == (Utilities::pow(3, dim) - 1) / 2)
              continue; // the key itself, searched first
            Key k = key;
            if (n >= 0) // the neighbours
              for (int d = 0, m = n; d < dim; ++d, m /= 3)
                k[d] += m % 3 - 1;
            const auto it = std::lower_bound(entries.begin(),
                                             entries.end(),
                                             k,
                                             [](const auto &e, const Key &k) {
                                               return e.first < k;
                                             });
            if (it != entries.end() && it->first == k)
              return &it->second;
          }
        return nullptr;
      }

      std::vector<std::pair<Key, T>> entries;

    private:
      Point<dim> box;
    };



    /**
     * The periodic face pairs of a regular grid (all cells on level 0) of
     * the box: the side x_d = L_d is the side x_d = 0 moved by L_d e_d, and
     * for d = 0 also by `shift` (wrapped into the box), which makes the
     * box a primitive cell of a sheared lattice.
     */
    template <typename Iterator, int dim>
    std::vector<GridTools::PeriodicFacePair<Iterator>>
    grid_face_pairs(const IteratorRange<Iterator> cells,
                    const Point<dim>             &box,
                    const Tensor<1, dim>         &shift)
    {
      std::vector<GridTools::PeriodicFacePair<Iterator>> pairs;
      for (unsigned int d = 0; d < dim; ++d)
        {
          // Face centers by their coordinates across direction d, wrapped.
          auto key = [&](Point<dim> c) {
            std::array<long long, dim> k{};
            for (unsigned int e = 0; e < dim; ++e)
              if (e != d)
                {
                  c[e] = std::fmod(c[e], box[e]);
                  if (c[e] < 0)
                    c[e] += box[e];
                  k[e] =
                    std::llround(c[e] / (1e-9 * box[e])) % std::llround(1e9);
                }
            return k;
          };
          std::map<std::array<long long, dim>,
                   std::pair<Iterator, unsigned int>>
            upper;
          for (const auto &cell : cells)
            for (const unsigned int f : cell->face_indices())
              if (cell->at_boundary(f) &&
                  cell->face(f)->boundary_id() == 2 * d + 1)
                upper[key(cell->face(f)->center())] = {cell, f};
          for (const auto &cell : cells)
            for (const unsigned int f : cell->face_indices())
              if (cell->at_boundary(f) && cell->face(f)->boundary_id() == 2 * d)
                {
                  Point<dim> target = cell->face(f)->center();
                  if (d == 0)
                    target += shift;
                  const auto partner = upper.find(key(target));
                  AssertThrow(partner != upper.end(),
                              ExcMessage("homogenization grid: a face on "
                                         "the side x" +
                                         std::to_string(d) +
                                         " = 0 has no periodic partner (is "
                                         "the shift a multiple of the cell "
                                         "size?)"));
                  GridTools::PeriodicFacePair<Iterator> pair;
                  pair.cell[0]        = cell;
                  pair.cell[1]        = partner->second.first;
                  pair.face_idx[0]    = f;
                  pair.face_idx[1]    = partner->second.second;
                  pair.orientation[0] = true; // aligned, not flipped
                  pairs.push_back(pair);
                }
        }
      return pairs;
    }
  } // namespace



  template <int dim>
  struct PeriodicHomogenization<dim>::Impl
  {
    static constexpr unsigned int nv = n_voigt<dim>;

    /**
     * The stiffness of a cell is linear in its (constant) tensor:
     * K(V) = sum_ab V_ab int B_a^T B_b, with B the Voigt strain of the shape
     * functions. `pair` holds the symmetrized integrals for a <= b,
     * `integral` int B_a; for congruent cells (regular grids) they are
     * computed once.
     */
    struct Kernel
    {
      std::vector<FullMatrix<double>> pair;
      std::vector<Vector<double>>     integral;
      double                          measure = 0;
    };

    Impl(const MPI_Comm comm, const SolverParameters &solver)
      : comm(comm)
      , solver_parameters(solver)
      , dof_handler()
    {}

    void
    setup(const unsigned int degree, const Point<dim> &box);

    /// Periodicity (and symmetry) constraints, then setup_system().
    void
    make_constraints(const Point<dim> &box);

    /// w = 0 at one interior vertex.
    void
    fix_translations(const Point<dim> &box);

    /// Sparsity, matrix, null space, kernels for the closed constraints.
    void
    setup_system();

    /// The position of the cell's dof i (the mapping is linear).
    Point<dim>
    support_point(const typename DoFHandler<dim>::active_cell_iterator &cell,
                  const unsigned int                                    i) const
    {
      Point<dim> p;
      for (unsigned int v = 0; v < support_weights[i].size(); ++v)
        p += support_weights[i][v] * cell->vertex(v);
      return p;
    }

    void
    compute_kernel(const typename DoFHandler<dim>::active_cell_iterator &cell,
                   Kernel &kernel) const;

    /// Meshes whose cells differ: the cell's K = int B^T V B and loads
    /// F_c = -int B^T V A_c directly (pair kernels pay off only when the
    /// cells share them); returns the cell's measure.
    double
    cell_system(const typename DoFHandler<dim>::active_cell_iterator &cell,
                const Tensor<2, nv>                                  &V,
                FullMatrix<double>                                   &K,
                std::vector<Vector<double>>                          &F) const;

    /**
     * Add a cell's int (A_c + B w_c)^T V (A_d + B w_d)
     *   = |K| V_cd + V_c. (int B) w_d + V_d. (int B) w_c + w_c^T K(V) w_d
     * for its local fluctuations w_c to energy(c, d).
     */
    void
    add_mutual_energies(const Kernel                      &kernel,
                        const Tensor<2, nv>               &V,
                        const std::vector<Vector<double>> &w_local,
                        FullMatrix<double>                &energy) const;

    MPI_Comm                            comm;
    SolverParameters                    solver_parameters;
    std::unique_ptr<Triangulation<dim>> tria;
    std::unique_ptr<FiniteElement<dim>> fe;
    std::unique_ptr<Mapping<dim>>       mapping_owner;
    const Mapping<dim>                 *mapping = nullptr;
    std::unique_ptr<Quadrature<dim>>    quadrature;
    /// Vertex weights of the element's support points (linear mapping).
    std::vector<std::vector<double>> support_weights;
    DoFHandler<dim>                  dof_handler;
    AffineConstraints<double>        constraints;
    IndexSet                         owned, relevant;
    TrilinosWrappers::SparseMatrix   matrix;
    // One rank and a direct solver: sparse Cholesky (CHOLMOD, several times
    // faster than KLU), assembled in place, analysis kept across calls.
    // The matrix is T^T K T on the free dofs alone, u = T x: the
    // constraints (periodic ties, odd images, pins; homogeneous) resolve
    // once here instead of per cell, and half the rows of a symmetric
    // cell's matrix are not built at all.
    bool           serial_direct = false;
    SparseCholesky cholesky;
    /// Row i of T: the free dofs (and weights) dof i follows, in
    /// reduction_entries[reduction_start[i], reduction_start[i + 1]).
    std::vector<unsigned int>                    reduction_start;
    std::vector<std::pair<unsigned int, double>> reduction_entries;
    std::vector<TrilinosWrappers::MPI::Vector>   fluctuation; // ghosted
    std::vector<std::vector<double>>             translation_modes;
    bool                                         congruent_cells = false;
    Kernel                                       shared_kernel;
    mutable std::unique_ptr<FEValues<dim>>       fe_values;
    mutable std::vector<std::array<double, nv>>  strains, stresses;
    double                                       box_volume = 0;
    /// The last homogenize()'s cell tensors (Voigt), locally owned cells.
    std::vector<Tensor<2, nv>> cell_tensors;
    /// Grids: the side x_0 = L_0 is the side x_0 = 0 moved by L_0 e_0 +
    /// shift (wrapped into the box), and the inversion symmetry.
    GridLattice lattice;
  };



  template <int dim>
  void
  PeriodicHomogenization<dim>::Impl::setup(const unsigned int degree,
                                           const Point<dim>  &box)
  {
    box_volume = 1;
    for (unsigned int d = 0; d < dim; ++d)
      box_volume *= box[d];

    // Faces on x_d = 0 / x_d = box_d carry ids 2d / 2d + 1, others 2 dim.
    for (const auto &cell : tria->active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          {
            // Hole boundaries of perforated cells are not periodic.
            cell->face(f)->set_boundary_id(2 * dim);
            const Point<dim> c = cell->face(f)->center();
            for (unsigned int d = 0; d < dim; ++d)
              {
                const double tol = 1e-8 * box[d];
                if (std::abs(c[d]) < tol)
                  cell->face(f)->set_boundary_id(2 * d);
                else if (std::abs(c[d] - box[d]) < tol)
                  cell->face(f)->set_boundary_id(2 * d + 1);
              }
          }
    std::vector<
      GridTools::PeriodicFacePair<typename Triangulation<dim>::cell_iterator>>
      periodic;
    if (congruent_cells)
      periodic =
        grid_face_pairs(tria->cell_iterators_on_level(0), box, lattice.shift);
    else
      for (unsigned int d = 0; d < dim; ++d)
        GridTools::collect_periodic_faces(*tria, 2 * d, 2 * d + 1, d, periodic);
    for (unsigned int d = 0; d < dim; ++d)
      {
        unsigned int n = 0;
        for (const auto &pair : periodic)
          n += (pair.cell[0]->face(pair.face_idx[0])->boundary_id() == 2 * d);
        AssertThrow(n > 0 || tria->n_active_cells() == 0,
                    ExcMessage("the cell mesh has no matching faces on the "
                               "sides x" +
                               std::to_string(d) + " = 0 and x" +
                               std::to_string(d) +
                               " = L: a periodic cell needs them"));
      }
    tria->add_periodicity(periodic);

    const ReferenceCell reference = tria->get_reference_cells()[0];
    AssertThrow(tria->get_reference_cells().size() == 1,
                ExcMessage("mixed-element cell meshes are not supported"));
    if (reference.is_hyper_cube())
      fe = std::make_unique<FESystem<dim>>(FE_Q<dim>(degree), dim);
    else
      fe = std::make_unique<FESystem<dim>>(FE_SimplexP<dim>(degree), dim);
    mapping = &reference.template get_default_linear_mapping<dim>();
    support_weights.assign(fe->n_dofs_per_cell(),
                           std::vector<double>(reference.n_vertices()));
    for (unsigned int i = 0; i < fe->n_dofs_per_cell(); ++i)
      for (unsigned int v = 0; v < reference.n_vertices(); ++v)
        support_weights[i][v] =
          reference.d_linear_shape_function(fe->unit_support_point(i), v);
    quadrature = std::make_unique<Quadrature<dim>>(
      reference.template get_gauss_type_quadrature<dim>(degree + 1));

    dof_handler.reinit(*tria);
    dof_handler.distribute_dofs(*fe);
    owned = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);

    make_constraints(box);
    setup_system();
  }



  template <int dim>
  void
  PeriodicHomogenization<dim>::Impl::make_constraints(const Point<dim> &box)
  {
    constraints.clear();
    constraints.reinit(relevant);
    if (congruent_cells)
      DoFTools::make_periodicity_constraints<dim, dim, double>(
        grid_face_pairs(dof_handler.cell_iterators_on_level(0),
                        box,
                        lattice.shift),
        constraints);
    else
      {
        // Unstructured (shared, so every cell is here) meshes: deal.II 9.4's
        // make_periodicity_constraints mismatches the dofs of periodic
        // faces with opposite line orientations, as simplex meshes have.
        // Tie every dof on an upper side to the dof at its image in the
        // lowest corner of its periodic class instead, by support points.
        PositionIndex<dim, types::global_dof_index> lower_dofs(box);
        std::vector<
          std::tuple<Point<dim>, unsigned int, types::global_dof_index>>
                                             upper_dofs;
        std::vector<types::global_dof_index> local(fe->n_dofs_per_cell());
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->at_boundary())
            {
              cell->get_dof_indices(local);
              for (unsigned int i = 0; i < local.size(); ++i)
                {
                  Point<dim>         p = support_point(cell, i);
                  const unsigned int c = fe->system_to_component_index(i).first;
                  bool               upper = false, on_side = false;
                  // Snap to the sides (round-off of the mesh file).
                  for (unsigned int d = 0; d < dim; ++d)
                    {
                      const double tol = 1e-8 * box[d];
                      if (std::abs(p[d]) < tol)
                        p[d] = 0, on_side = true;
                      else if (std::abs(p[d] - box[d]) < tol)
                        p[d] = box[d], on_side = upper = true;
                    }
                  Point<dim> image = p;
                  for (unsigned int d = 0; d < dim; ++d)
                    if (p[d] == box[d])
                      image[d] = 0;
                  if (upper)
                    upper_dofs.emplace_back(image, c, local[i]);
                  else if (on_side)
                    lower_dofs.insert(p, c, local[i]);
                }
            }
        lower_dofs.sort();
        for (const auto &[image, c, i] : upper_dofs)
          {
            const types::global_dof_index *partner = lower_dofs.find(image, c);
            AssertThrow(partner != nullptr,
                        ExcMessage("the cell mesh is not periodic: a node on "
                                   "an upper side has no partner on the "
                                   "opposite side"));
            if (constraints.can_store_line(i) && !constraints.is_constrained(i))
              {
                constraints.add_line(i);
                constraints.add_entry(i, *partner, 1.);
              }
          }
      }

    // Odd fluctuations about the inversion center: w_j = -w_i for the dofs
    // at points p and its image 2c - p (wrapped into the lattice's
    // fundamental domain), w = 0 where they coincide. Constants are not
    // odd, so this also removes the translations.
    if (lattice.inversion && Utilities::MPI::n_mpi_processes(comm) == 1)
      {
        const auto wrap = [&](Point<dim> q) {
          const double k0 = std::floor(q[0] / box[0] + 1e-9);
          q[0] -= k0 * box[0];
          for (unsigned int d = 1; d < dim; ++d)
            {
              q[d] -= k0 * lattice.shift[d];
              q[d] -= std::floor(q[d] / box[d] + 1e-9) * box[d];
            }
          return q;
        };
        // The unconstrained dofs by their position wrapped into the
        // fundamental domain [0, box).
        PositionIndex<dim, std::pair<Point<dim>, types::global_dof_index>>
                                             free_dofs(box);
        std::vector<types::global_dof_index> local(fe->n_dofs_per_cell());
        std::vector<bool>                    seen(dof_handler.n_dofs());
        free_dofs.entries.reserve(dof_handler.n_dofs());
        for (const auto &cell : dof_handler.active_cell_iterators())
          {
            cell->get_dof_indices(local);
            for (unsigned int i = 0; i < local.size(); ++i)
              if (!seen[local[i]] && !constraints.is_constrained(local[i]))
                {
                  seen[local[i]]     = true;
                  const Point<dim> p = support_point(cell, i);
                  free_dofs.insert(wrap(p),
                                   fe->system_to_component_index(i).first,
                                   {p, local[i]});
                }
          }
        free_dofs.sort();
        unsigned int fixed = 0;
        for (const auto &[k, point_dof] : free_dofs.entries)
          {
            const auto &[p, i] = point_dof;
            const auto *image =
              free_dofs.find(wrap(Point<dim>(2 * lattice.inversion_center - p)),
                             k[dim]);
            AssertThrow(image != nullptr,
                        ExcMessage(
                          "homogenization: the mesh is not symmetric under "
                          "the inversion about its center (no node at the "
                          "image of a node)"));
            const types::global_dof_index j = image->second;
            if (j == i)
              {
                constraints.add_line(i);
                ++fixed;
              }
            else if (i < j)
              {
                constraints.add_line(j);
                constraints.add_entry(j, i, -1.);
              }
          }
        // Grids keep a vertex at the center (the structures' assumption).
        AssertThrow(!congruent_cells || fixed >= dim,
                    ExcMessage("homogenization grid: the inversion center "
                               "must be a grid vertex"));
        constraints.close();
      }
    else
      fix_translations(box);
  }



  template <int dim>
  void
  PeriodicHomogenization<dim>::Impl::fix_translations(const Point<dim> &box)
  {
    // Remove the translations: w = 0 at the interior vertex nearest the
    // center (interior, so it is not tied to periodic partners).
    Point<dim> center;
    for (unsigned int d = 0; d < dim; ++d)
      center[d] = box[d] / 2;
    std::pair<double, types::global_dof_index> best = {
      std::numeric_limits<double>::max(), 0};
    std::vector<types::global_dof_index> vertex_dofs(dim);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int v : cell->vertex_indices())
          {
            bool interior = true;
            for (unsigned int d = 0; d < dim; ++d)
              interior &= cell->vertex(v)[d] > 1e-8 * box[d] &&
                          cell->vertex(v)[d] < (1 - 1e-8) * box[d];
            if (!interior)
              continue;
            const double dist                = cell->vertex(v).distance(center);
            const types::global_dof_index i0 = cell->vertex_dof_index(v, 0);
            if (dist < best.first - 1e-12 ||
                (dist < best.first + 1e-12 && i0 < best.second))
              {
                best = {dist, i0};
                for (unsigned int c = 0; c < dim; ++c)
                  vertex_dofs[c] = cell->vertex_dof_index(v, c);
              }
          }
    const auto   all  = Utilities::MPI::all_gather(comm, best);
    const auto   dofs = Utilities::MPI::all_gather(comm, vertex_dofs);
    unsigned int rank = numbers::invalid_unsigned_int;
    for (unsigned int r = 0; r < all.size(); ++r)
      if (all[r].first < std::numeric_limits<double>::max() &&
          (rank == numbers::invalid_unsigned_int ||
           all[r].first < all[rank].first - 1e-12 ||
           (all[r].first < all[rank].first + 1e-12 &&
            all[r].second < all[rank].second)))
        rank = r;
    AssertThrow(rank != numbers::invalid_unsigned_int,
                ExcMessage("the cell mesh has no interior vertex; use at "
                           "least 2 cells per direction"));
    for (const types::global_dof_index i : dofs[rank])
      if (constraints.can_store_line(i))
        constraints.add_line(i);
    constraints.close();
  }



  template <int dim>
  void
  PeriodicHomogenization<dim>::Impl::setup_system()
  {
    // auto counts the unknowns left by the constraints (serial).
    const types::global_dof_index unknowns =
      dof_handler.n_dofs() - (Utilities::MPI::n_mpi_processes(comm) == 1 ?
                                constraints.n_constraints() :
                                0);
    const std::string type =
      solver_parameters.type == "auto" ?
        (unknowns <= solver_parameters.direct_limit ? "direct" : "cg-amg") :
        solver_parameters.type;
    AssertThrow(type == "direct" || type == "cg-amg",
                ExcMessage("unknown homogenization solver '" + type +
                           "' (auto | direct | cg-amg)"));
    solver_parameters.type = type;
    serial_direct =
      type == "direct" && Utilities::MPI::n_mpi_processes(comm) == 1;
    if (serial_direct)
      {
        const types::global_dof_index n_dofs = dof_handler.n_dofs();
        std::vector<unsigned int>     free_index(n_dofs,
                                             numbers::invalid_unsigned_int);
        unsigned int                  n_free = 0;
        AssertThrow(constraints.is_closed(), ExcInternalError());
        for (types::global_dof_index i = 0; i < n_dofs; ++i)
          if (!constraints.is_constrained(i))
            free_index[i] = n_free++;
        reduction_start.assign(1, 0);
        reduction_start.reserve(n_dofs + 1);
        reduction_entries.clear();
        reduction_entries.reserve(n_dofs);
        for (types::global_dof_index i = 0; i < n_dofs; ++i)
          {
            if (free_index[i] != numbers::invalid_unsigned_int)
              reduction_entries.emplace_back(free_index[i], 1.);
            else
              {
                AssertThrow(!constraints.is_inhomogeneously_constrained(i),
                            ExcInternalError());
                // Closed: the entries are free dofs.
                for (const auto &[j, weight] :
                     *constraints.get_constraint_entries(i))
                  reduction_entries.emplace_back(free_index[j], weight);
              }
            reduction_start.push_back(reduction_entries.size());
          }
        DynamicSparsityPattern               dsp(n_free);
        std::vector<unsigned int>            rows;
        std::vector<types::global_dof_index> local(fe->n_dofs_per_cell());
        for (const auto &cell : dof_handler.active_cell_iterators())
          {
            cell->get_dof_indices(local);
            rows.clear();
            for (const types::global_dof_index i : local)
              for (unsigned int k = reduction_start[i];
                   k < reduction_start[i + 1];
                   ++k)
                rows.push_back(reduction_entries[k].first);
            std::sort(rows.begin(), rows.end());
            rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
            // Entries (r, c <= r): the half SparseCholesky keeps.
            for (auto r = rows.begin(); r != rows.end(); ++r)
              dsp.add_entries(*r, rows.begin(), r + 1, true);
          }
        cholesky.reinit(dsp);
      }
    else
      {
        DynamicSparsityPattern dsp(relevant);
        DoFTools::make_sparsity_pattern(dof_handler, dsp, constraints, false);
        SparsityTools::distribute_sparsity_pattern(dsp, owned, comm, relevant);
        matrix.reinit(owned, owned, dsp, comm);
      }

    // Translations for the AMG near null space.
    translation_modes.clear();
    if (!serial_direct)
      {
        translation_modes.assign(dim, std::vector<double>(owned.n_elements()));
        std::vector<types::global_dof_index> local(fe->n_dofs_per_cell());
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              cell->get_dof_indices(local);
              for (unsigned int i = 0; i < local.size(); ++i)
                if (owned.is_element(local[i]))
                  translation_modes[fe->system_to_component_index(i).first]
                                   [owned.index_within_set(local[i])] = 1;
            }
      }

    // Regular grids: every cell is a translate of the first.
    if (congruent_cells)
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            compute_kernel(cell, shared_kernel);
            break;
          }
  }



  template <int dim>
  void
  PeriodicHomogenization<dim>::Impl::compute_kernel(
    const typename DoFHandler<dim>::active_cell_iterator &cell,
    Kernel                                               &kernel) const
  {
    // One FEValues and kernel storage for all cells of a mesh: this runs
    // per cell and per homogenize() on unstructured meshes.
    if (!fe_values)
      fe_values = std::make_unique<FEValues<dim>>(
        *mapping, *fe, *quadrature, update_gradients | update_JxW_values);
    fe_values->reinit(cell);
    const unsigned int n = fe->n_dofs_per_cell();
    if (kernel.pair.size() != nv * (nv + 1) / 2)
      {
        kernel.pair.assign(nv * (nv + 1) / 2, FullMatrix<double>(n, n));
        kernel.integral.assign(nv, Vector<double>(n));
      }
    for (auto &P : kernel.pair)
      P = 0;
    for (auto &g : kernel.integral)
      g = 0;
    kernel.measure = 0;
    const FEValuesExtractors::Vector     displacement(0);
    std::vector<std::array<double, nv>> &B = strains;
    B.resize(n);
    for (const unsigned int q : fe_values->quadrature_point_indices())
      {
        const double JxW = fe_values->JxW(q);
        kernel.measure += JxW;
        for (unsigned int i = 0; i < n; ++i)
          strain_to_voigt<dim>((*fe_values)[displacement].symmetric_gradient(i,
                                                                             q),
                               B[i].data());
        unsigned int p = 0;
        for (unsigned int a = 0; a < nv; ++a)
          for (unsigned int b = a; b < nv; ++b, ++p)
            for (unsigned int i = 0; i < n; ++i)
              for (unsigned int j = 0; j < n; ++j)
                kernel.pair[p](i, j) +=
                  (a == b ? B[i][a] * B[j][a] :
                            B[i][a] * B[j][b] + B[i][b] * B[j][a]) *
                  JxW;
        for (unsigned int a = 0; a < nv; ++a)
          for (unsigned int i = 0; i < n; ++i)
            kernel.integral[a](i) += B[i][a] * JxW;
      }
  }



  template <int dim>
  double
  PeriodicHomogenization<dim>::Impl::cell_system(
    const typename DoFHandler<dim>::active_cell_iterator &cell,
    const Tensor<2, nv>                                  &V,
    FullMatrix<double>                                   &K,
    std::vector<Vector<double>>                          &F) const
  {
    if (!fe_values)
      fe_values = std::make_unique<FEValues<dim>>(
        *mapping, *fe, *quadrature, update_gradients | update_JxW_values);
    fe_values->reinit(cell);
    const unsigned int n = fe->n_dofs_per_cell();
    K                    = 0;
    for (auto &f : F)
      f = 0;
    strains.resize(n);
    stresses.resize(n);
    double measure = 0;
    for (const unsigned int q : fe_values->quadrature_point_indices())
      {
        const double JxW = fe_values->JxW(q);
        measure += JxW;
        for (unsigned int i = 0; i < n; ++i)
          {
            // Shape function i moves component c only (primitive FESystem).
            const unsigned int    c = fe->system_to_component_index(i).first;
            const Tensor<1, dim> &g = fe_values->shape_grad(i, q);
            for (unsigned int a = 0; a < nv; ++a)
              {
                const auto [k, l] = voigt_pair<dim>(a);
                strains[i][a] =
                  (c == k ? g[l] : 0.) + (k != l && c == l ? g[k] : 0.);
              }
            for (unsigned int a = 0; a < nv; ++a)
              {
                double sigma = 0;
                for (unsigned int b = 0; b < nv; ++b)
                  sigma += V[a][b] * strains[i][b];
                stresses[i][a] = sigma * JxW;
              }
          }
        for (unsigned int i = 0; i < n; ++i)
          {
            for (unsigned int j = 0; j <= i; ++j)
              {
                double k = 0;
                for (unsigned int a = 0; a < nv; ++a)
                  k += strains[i][a] * stresses[j][a];
                K(i, j) += k;
              }
            // (B^T V A_c)_i = (V B_i)_c, V symmetric
            for (unsigned int c = 0; c < nv; ++c)
              F[c](i) -= stresses[i][c];
          }
      }
    for (unsigned int i = 0; i < n; ++i)
      for (unsigned int j = i + 1; j < n; ++j)
        K(i, j) = K(j, i);
    return measure;
  }



  template <int dim>
  PeriodicHomogenization<dim>::PeriodicHomogenization(
    const MPI_Comm                       comm,
    const Point<dim>                    &size,
    const std::array<unsigned int, dim> &n_cells,
    const SolverParameters              &solver,
    const unsigned int                   degree,
    const GridLattice                   &lattice)
    : impl(std::make_unique<Impl>(comm, solver))
  {
    const Tensor<1, dim> &shift = lattice.shift;
    AssertThrow(shift[0] == 0,
                ExcMessage("the homogenization grid's shift must be across "
                           "direction 0"));
    for (unsigned int d = 0; d < dim; ++d)
      {
        AssertThrow(size[d] > 0,
                    ExcMessage("the homogenization cell needs a positive "
                               "size in every direction"));
        AssertThrow(n_cells[d] >= 2,
                    ExcMessage("the homogenization grid needs at least 2 "
                               "cells per direction"));
        const double cells = shift[d] * n_cells[d] / size[d];
        AssertThrow(std::abs(cells - std::round(cells)) < 1e-8,
                    ExcMessage("the homogenization grid's shift must be a "
                               "multiple of the cell size"));
      }
    auto tria =
      std::make_unique<parallel::distributed::Triangulation<dim>>(comm);
    std::vector<unsigned int> repetitions(n_cells.begin(), n_cells.end());
    GridGenerator::subdivided_hyper_rectangle(*tria,
                                              repetitions,
                                              Point<dim>(),
                                              size);
    impl->tria            = std::move(tria);
    impl->congruent_cells = true;
    impl->lattice         = lattice;
    impl->setup(degree, size);
  }



  template <int dim>
  PeriodicHomogenization<dim>::PeriodicHomogenization(
    const MPI_Comm                 comm,
    const Triangulation<dim, dim> &mesh,
    const SolverParameters        &solver,
    const unsigned int             degree)
    : impl(std::make_unique<Impl>(comm, solver))
  {
    AssertThrow(mesh.n_active_cells() > 0,
                ExcMessage("the homogenization mesh is empty"));
    Point<dim> lo = mesh.get_vertices()[0], hi = lo;
    for (const auto &v : mesh.get_vertices())
      for (unsigned int d = 0; d < dim; ++d)
        {
          lo[d] = std::min(lo[d], v[d]);
          hi[d] = std::max(hi[d], v[d]);
        }
    AssertThrow(lo.norm() <= 1e-8 * hi.norm(),
                ExcMessage("the homogenization mesh must fill the box "
                           "[0, L1] x [0, L2] (its lower corner is not at "
                           "the origin)"));
    auto tria = std::make_unique<parallel::shared::Triangulation<dim>>(comm);
    tria->copy_triangulation(mesh);
    impl->tria = std::move(tria);
    impl->setup(degree, hi);
  }



  template <int dim>
  PeriodicHomogenization<dim>::PeriodicHomogenization(
    const MPI_Comm                 comm,
    const Triangulation<dim, dim> &mesh,
    const Point<dim>              &box,
    const SolverParameters        &solver,
    const unsigned int             degree,
    const bool                     inversion_symmetric)
    : impl(std::make_unique<Impl>(comm, solver))
  {
    AssertThrow(mesh.n_active_cells() > 0,
                ExcMessage("the homogenization mesh is empty"));
    for (const auto &v : mesh.get_vertices())
      for (unsigned int d = 0; d < dim; ++d)
        AssertThrow(v[d] >= -1e-8 * box[d] && v[d] <= box[d] * (1 + 1e-8),
                    ExcMessage("the homogenization mesh reaches out of the "
                               "box [0, L]"));
    auto tria = std::make_unique<parallel::shared::Triangulation<dim>>(comm);
    tria->copy_triangulation(mesh);
    impl->tria                     = std::move(tria);
    impl->lattice.inversion        = inversion_symmetric;
    impl->lattice.inversion_center = 0.5 * box;
    impl->setup(degree, box);
  }



  template <int dim>
  PeriodicHomogenization<dim>::~PeriodicHomogenization() = default;



  template <int dim>
  typename PeriodicHomogenization<dim>::Result
  PeriodicHomogenization<dim>::homogenize(const MaterialFunction &material)
  {
    Impl              &m  = *impl;
    constexpr unsigned nv = Impl::nv;
    const unsigned int n  = m.fe->n_dofs_per_cell();

    // One pass: the matrix and the right-hand sides of all test strains.
    if (m.serial_direct)
      m.cholesky.set_zero();
    else
      m.matrix = 0;
    // The right-hand sides: T^T F on the free dofs (serial direct) or the
    // condensed F.
    const unsigned int n_free = m.serial_direct ? m.cholesky.size() : 0;
    std::vector<Vector<double>> free_rhs(m.serial_direct ? nv : 0,
                                         Vector<double>(n_free));
    std::vector<TrilinosWrappers::MPI::Vector> rhs;
    if (!m.serial_direct)
      rhs.assign(nv, TrilinosWrappers::MPI::Vector(m.owned, m.comm));
    // Adds the cell's K and F to T^T K T and T^T F: (local dof, free dof,
    // weight) for the cell's rows of T.
    std::vector<std::tuple<unsigned int, unsigned int, double>> cell_T;
    std::vector<unsigned int>                                   columns;
    std::vector<double>                                         values;
    const auto                                                  add_reduced =
      [&](const FullMatrix<double>                   &K,
          const std::vector<Vector<double>>          &F,
          const std::vector<types::global_dof_index> &local) {
        cell_T.clear();
        for (unsigned int i = 0; i < local.size(); ++i)
          for (unsigned int k = m.reduction_start[local[i]];
               k < m.reduction_start[local[i] + 1];
               ++k)
            cell_T.emplace_back(i,
                                m.reduction_entries[k].first,
                                m.reduction_entries[k].second);
        for (const auto &[i, r, t_i] : cell_T)
          {
            // Entries (r, c <= r): the half SparseCholesky keeps.
            columns.clear();
            values.clear();
            for (const auto &[j, c, t_j] : cell_T)
              if (c <= r)
                {
                  columns.push_back(c);
                  values.push_back(t_i * t_j * K(i, j));
                }
            // A free dof met twice (a cell holding a dof and its image)
            // adds up.
            m.cholesky.add_row(r,
                               columns.size(),
                               columns.data(),
                               values.data());
            for (unsigned int c = 0; c < nv; ++c)
              free_rhs[c](r) += t_i * F[c](i);
          }
      };
    FullMatrix<double>                   average(nv, nv); // int_Y V
    FullMatrix<double>                   K(n, n);
    std::vector<Vector<double>>          F(nv, Vector<double>(n));
    std::vector<types::global_dof_index> local(n);
    typename Impl::Kernel                own_kernel;
    std::vector<Tensor<2, nv>>          &cell_tensor = m.cell_tensors;
    cell_tensor.clear();
    cell_tensor.reserve(m.tria->n_active_cells());
    for (const auto &cell : m.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const SymmetricTensor<4, dim> C =
            material(cell->center(), cell->material_id());
          Tensor<2, nv> V;
          for (unsigned int a = 0; a < nv; ++a)
            for (unsigned int b = 0; b < nv; ++b)
              {
                const auto [i, j] = voigt_pair<dim>(a);
                const auto [k, l] = voigt_pair<dim>(b);
                V[a][b]           = C[i][j][k][l];
              }
          cell_tensor.push_back(V);
          double measure;
          if (m.congruent_cells)
            {
              const auto &kernel = m.shared_kernel;
              measure            = kernel.measure;
              K                  = 0;
              unsigned int p     = 0;
              for (unsigned int a = 0; a < nv; ++a)
                for (unsigned int b = a; b < nv; ++b, ++p)
                  K.add(V[a][b], kernel.pair[p]);
              // f_c = -int B^T C A_c = -sum_a V_ac int B_a
              for (unsigned int c = 0; c < nv; ++c)
                {
                  F[c] = 0;
                  for (unsigned int a = 0; a < nv; ++a)
                    F[c].add(-V[a][c], kernel.integral[a]);
                }
            }
          else
            measure = m.cell_system(cell, V, K, F);
          for (unsigned int a = 0; a < nv; ++a)
            for (unsigned int b = 0; b < nv; ++b)
              average(a, b) += measure * V[a][b];
          cell->get_dof_indices(local);
          if (m.serial_direct)
            add_reduced(K, F, local);
          else
            {
              m.constraints.distribute_local_to_global(K, local, m.matrix);
              for (unsigned int c = 0; c < nv; ++c)
                m.constraints.distribute_local_to_global(F[c], local, rhs[c]);
            }
        }
    if (!m.serial_direct)
      m.matrix.compress(VectorOperation::add);
    for (auto &r : rhs)
      r.compress(VectorOperation::add);

    Result result;
    result.solver = m.solver_parameters.type;
    m.fluctuation.resize(nv);
    std::vector<TrilinosWrappers::MPI::Vector> w;
    if (!m.serial_direct)
      w.assign(nv, TrilinosWrappers::MPI::Vector(m.owned, m.comm));
    // f_c . w_d (f_c the condensed right-hand side, w_d the solution).
    FullMatrix<double> load_work(nv, nv);
    if (m.serial_direct)
      {
        m.cholesky.factorize();
        std::vector<Vector<double>> x = free_rhs;
        Vector<double>              u(m.dof_handler.n_dofs());
        for (unsigned int c = 0; c < nv; ++c)
          {
            m.cholesky.solve(x[c]);
            for (types::global_dof_index i = 0; i < u.size(); ++i)
              {
                double value = 0;
                for (unsigned int k = m.reduction_start[i];
                     k < m.reduction_start[i + 1];
                     ++k)
                  value += m.reduction_entries[k].second *
                           x[c](m.reduction_entries[k].first);
                u(i) = value;
              }
            m.fluctuation[c].reinit(m.owned, m.relevant, m.comm);
            m.fluctuation[c] = u;
            result.linear_iterations.push_back(1);
          }
        for (unsigned int c = 0; c < nv; ++c)
          for (unsigned int d = 0; d < nv; ++d)
            load_work(c, d) = free_rhs[c] * x[d];
      }
    else
      {
        LinearSolver::Parameters lp;
        lp.type               = m.solver_parameters.type;
        lp.relative_tolerance = m.solver_parameters.tolerance;
        lp.max_iterations     = 5000;
        LinearSolver solver(lp);
        solver.set_null_space(m.translation_modes);
        for (unsigned int c = 0; c < nv; ++c)
          result.linear_iterations.push_back(
            c == 0 ? solver.solve(m.matrix, w[c], rhs[c], false) :
                     solver.solve_reusing(m.matrix, w[c], rhs[c]));
      }
    for (unsigned int c = 0; c < w.size(); ++c) // u = T x needs none of it
      {
        for (unsigned int d = 0; d < nv; ++d)
          load_work(d, c) = rhs[d] * w[c];
        m.constraints.distribute(w[c]);
        m.fluctuation[c].reinit(m.owned, m.relevant, m.comm);
        m.fluctuation[c] = w[c];
      }

    FullMatrix<double> energy(nv, nv);
    if (!m.congruent_cells && m.solver_parameters.type == "direct")
      {
        // Unstructured meshes, whose kernels are per cell: as w_c is
        // stationary, a(chi_c, chi_d) = a(A_c x, chi_d) = int V_cd - f_c . w_d
        // (f_c the condensed right-hand side): no second pass over the cells.
        // Exact at stationarity, so only after direct solves.
        for (unsigned int c = 0; c < nv; ++c)
          for (unsigned int d = 0; d < nv; ++d)
            energy(c, d) =
              Utilities::MPI::sum(average(c, d), m.comm) - load_work(c, d);
        for (unsigned int c = 0; c < nv; ++c)
          for (unsigned int d = 0; d < nv; ++d)
            {
              const double e       = 0.5 * (energy(c, d) + energy(d, c));
              const auto [i, j]    = voigt_pair<dim>(c);
              const auto [k, l]    = voigt_pair<dim>(d);
              result.C[i][j][k][l] = e / m.box_volume;
            }
        return result;
      }

    // Grids (shared kernels): mutual energies cell by cell, symmetric and
    // positive definite by construction.
    std::vector<Vector<double>> w_local(nv, Vector<double>(n));
    unsigned int                index = 0;
    for (const auto &cell : m.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const Tensor<2, nv> &V = cell_tensor[index++];
          if (!m.congruent_cells)
            m.compute_kernel(cell, own_kernel);
          const auto &kernel = m.congruent_cells ? m.shared_kernel : own_kernel;
          cell->get_dof_indices(local);
          for (unsigned int c = 0; c < nv; ++c)
            for (unsigned int i = 0; i < n; ++i)
              w_local[c](i) = m.fluctuation[c](local[i]);
          m.add_mutual_energies(kernel, V, w_local, energy);
        }
    for (unsigned int c = 0; c < nv; ++c)
      for (unsigned int d = 0; d < nv; ++d)
        {
          // Mutual energies of engineering unit strains are the Voigt
          // entries; symmetrize the round-off away (SymmetricTensor<4>
          // stores both C_ijkl and C_klij).
          const double e =
            Utilities::MPI::sum(0.5 * (energy(c, d) + energy(d, c)), m.comm);
          const auto [i, j]    = voigt_pair<dim>(c);
          const auto [k, l]    = voigt_pair<dim>(d);
          result.C[i][j][k][l] = e / m.box_volume;
        }
    return result;
  }



  template <int dim>
  void
  PeriodicHomogenization<dim>::write_vtu(
    const std::string              &file_stem,
    const std::vector<std::string> &cell_data_names,
    const std::function<std::vector<double>(const Point<dim> &,
                                            const types::material_id)>
      &cell_data) const
  {
    write_vtu(file_stem,
              cell_data_names,
              cell_data,
              Tensor<2, dim>(unit_symmetric_tensor<dim>()));
  }



  template <int dim>
  void
  PeriodicHomogenization<dim>::Impl::add_mutual_energies(
    const Kernel                      &kernel,
    const Tensor<2, nv>               &V,
    const std::vector<Vector<double>> &w_local,
    FullMatrix<double>                &energy) const
  {
    const unsigned int n = w_local[0].size();
    FullMatrix<double> K(n, n);
    unsigned int       p = 0;
    for (unsigned int a = 0; a < nv; ++a)
      for (unsigned int b = a; b < nv; ++b, ++p)
        K.add(V[a][b], kernel.pair[p]);
    // s_a(w) = int (B w)_a
    std::array<std::array<double, nv>, nv> s;
    for (unsigned int c = 0; c < nv; ++c)
      for (unsigned int a = 0; a < nv; ++a)
        s[c][a] = kernel.integral[a] * w_local[c];
    Vector<double> Kw(n);
    for (unsigned int d = 0; d < nv; ++d)
      {
        K.vmult(Kw, w_local[d]);
        for (unsigned int c = 0; c < nv; ++c)
          {
            double e = kernel.measure * V[c][d] + (w_local[c] * Kw);
            for (unsigned int a = 0; a < nv; ++a)
              e += V[c][a] * s[d][a] + V[d][a] * s[c][a];
            energy(c, d) += e;
          }
      }
  }



  template <int dim>
  std::vector<SymmetricTensor<4, dim>>
  PeriodicHomogenization<dim>::material_gradient(
    const MaterialDerivativeFunction &material_derivative,
    const unsigned int                n_parameters) const
  {
    const Impl        &m  = *impl;
    constexpr unsigned nv = Impl::nv;
    AssertThrow(m.fluctuation.size() == nv,
                ExcMessage("material_gradient() needs a homogenize() first"));
    const unsigned int                   n = m.fe->n_dofs_per_cell();
    std::vector<FullMatrix<double>>      energy(n_parameters,
                                           FullMatrix<double>(nv, nv));
    std::vector<Vector<double>>          w_local(nv, Vector<double>(n));
    std::vector<types::global_dof_index> local(n);
    typename Impl::Kernel                own_kernel;
    std::size_t                          wrong_size = 0;
    for (const auto &cell : m.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const std::vector<SymmetricTensor<4, dim>> dC =
            material_derivative(cell->center(), cell->material_id());
          // Checked on every rank after the loop (a throw here would leave
          // the other ranks in the sums).
          if (dC.size() != n_parameters)
            {
              wrong_size = dC.size();
              continue;
            }
          bool loaded = false;
          for (unsigned int q = 0; q < n_parameters; ++q)
            {
              if (dC[q].norm() == 0)
                continue;
              if (!loaded)
                {
                  if (!m.congruent_cells)
                    m.compute_kernel(cell, own_kernel);
                  cell->get_dof_indices(local);
                  for (unsigned int c = 0; c < nv; ++c)
                    for (unsigned int i = 0; i < n; ++i)
                      w_local[c](i) = m.fluctuation[c](local[i]);
                  loaded = true;
                }
              Tensor<2, nv> dV;
              for (unsigned int a = 0; a < nv; ++a)
                for (unsigned int b = 0; b < nv; ++b)
                  {
                    const auto [i, j] = voigt_pair<dim>(a);
                    const auto [k, l] = voigt_pair<dim>(b);
                    dV[a][b]          = dC[q][i][j][k][l];
                  }
              m.add_mutual_energies(m.congruent_cells ? m.shared_kernel :
                                                        own_kernel,
                                    dV,
                                    w_local,
                                    energy[q]);
            }
        }
    wrong_size = Utilities::MPI::max(wrong_size, m.comm);
    AssertThrow(wrong_size == 0,
                ExcMessage("material_gradient(): the material derivative has " +
                           std::to_string(wrong_size) + " entries, expected " +
                           std::to_string(n_parameters)));
    // One reduction for every parameter and pair.
    std::vector<double> packed;
    for (unsigned int q = 0; q < n_parameters; ++q)
      for (unsigned int c = 0; c < nv; ++c)
        for (unsigned int d = 0; d < nv; ++d)
          packed.push_back(0.5 * (energy[q](c, d) + energy[q](d, c)));
    Utilities::MPI::sum(packed, m.comm, packed);
    std::vector<SymmetricTensor<4, dim>> result(n_parameters);
    unsigned int                         index = 0;
    for (unsigned int q = 0; q < n_parameters; ++q)
      for (unsigned int c = 0; c < nv; ++c)
        for (unsigned int d = 0; d < nv; ++d)
          {
            const auto [i, j]     = voigt_pair<dim>(c);
            const auto [k, l]     = voigt_pair<dim>(d);
            result[q][i][j][k][l] = packed[index++] / m.box_volume;
          }
    return result;
  }



  template <int dim>
  std::vector<std::array<SymmetricTensor<4, dim>, dim>>
  PeriodicHomogenization<dim>::vertex_shape_gradient() const
  {
    const Impl        &m  = *impl;
    constexpr unsigned nv = Impl::nv;
    AssertThrow(m.fluctuation.size() == nv,
                ExcMessage("vertex_shape_gradient() needs a homogenize() "
                           "first"));
    AssertThrow(!m.congruent_cells || !m.lattice.inversion,
                ExcMessage("vertex_shape_gradient() is for cell meshes"));
    // The geometry's own linear shape functions carry the vertex motion.
    const ReferenceCell reference = m.tria->get_reference_cells()[0];
    std::unique_ptr<FiniteElement<dim>> linear;
    if (reference.is_hyper_cube())
      linear = std::make_unique<FE_Q<dim>>(1);
    else
      linear = std::make_unique<FE_SimplexP<dim>>(1);
    FEValues<dim> fv(*m.mapping,
                     *m.fe,
                     *m.quadrature,
                     update_gradients | update_JxW_values);
    FEValues<dim> lv(*m.mapping, *linear, *m.quadrature, update_gradients);
    const FEValuesExtractors::Vector displacement(0);
    const unsigned int n = m.fe->n_dofs_per_cell(), nq = m.quadrature->size();
    std::vector<std::vector<Tensor<2, dim>>> grad_w(
      nv, std::vector<Tensor<2, dim>>(nq));
    std::vector<types::global_dof_index> local(n);
    // g[(v * dim + k) * nv * nv + a * nv + b] = dC_ab / dX_vk
    std::vector<double> g(m.tria->n_vertices() * dim * nv * nv, 0.);
    unsigned int        index = 0;
    for (const auto &cell : m.dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const Tensor<2, nv> &V = m.cell_tensors[index++];
          fv.reinit(cell);
          lv.reinit(typename Triangulation<dim>::active_cell_iterator(cell));
          cell->get_dof_indices(local);
          for (unsigned int c = 0; c < nv; ++c)
            {
              std::fill(grad_w[c].begin(), grad_w[c].end(), Tensor<2, dim>());
              for (unsigned int i = 0; i < n; ++i)
                {
                  const double wi = m.fluctuation[c](local[i]);
                  if (wi != 0)
                    for (unsigned int q = 0; q < nq; ++q)
                      grad_w[c][q] += wi * fv[displacement].gradient(i, q);
                }
            }
          for (unsigned int q = 0; q < nq; ++q)
            {
              // Total strains (Voigt) and stresses (tensors) of the cases.
              std::array<std::array<double, nv>, nv> e;
              std::array<Tensor<2, dim>, nv>         sigma;
              for (unsigned int a = 0; a < nv; ++a)
                {
                  strain_to_voigt<dim>(test_strain<dim>(a) +
                                         symmetrize(grad_w[a][q]),
                                       e[a].data());
                  std::array<double, nv> sv{};
                  for (unsigned int r = 0; r < nv; ++r)
                    for (unsigned int t = 0; t < nv; ++t)
                      sv[r] += V[r][t] * e[a][t];
                  for (unsigned int r = 0; r < nv; ++r)
                    {
                      const auto [i, j] = voigt_pair<dim>(r);
                      sigma[a][i][j] = sigma[a][j][i] = sv[r];
                    }
                }
              // Per pair, once per point: the energy density and
              // M_ab = grad w_a^T sigma_b, so that the vertex terms are
              // (e_ab I - M_ab - M_ba) grad lambda_v.
              const double JxW = fv.JxW(q) / m.box_volume;
              std::array<std::array<Tensor<2, dim>, nv>, nv> K;
              for (unsigned int a = 0; a < nv; ++a)
                for (unsigned int b = 0; b < nv; ++b)
                  K[a][b] = transpose(grad_w[a][q]) * sigma[b];
              std::array<std::array<Tensor<2, dim>, nv>, nv> T;
              for (unsigned int a = 0; a < nv; ++a)
                for (unsigned int b = a; b < nv; ++b)
                  {
                    double energy = 0;
                    for (unsigned int r = 0; r < nv; ++r)
                      for (unsigned int t = 0; t < nv; ++t)
                        energy += e[a][r] * V[r][t] * e[b][t];
                    T[a][b] = JxW * (energy * unit_symmetric_tensor<dim>() -
                                     K[a][b] - K[b][a]);
                  }
              for (unsigned int v = 0; v < cell->n_vertices(); ++v)
                {
                  const Tensor<1, dim> gl = lv.shape_grad(v, q);
                  const unsigned int   vi = cell->vertex_index(v);
                  for (unsigned int a = 0; a < nv; ++a)
                    for (unsigned int b = a; b < nv; ++b)
                      {
                        const Tensor<1, dim> d = T[a][b] * gl;
                        for (unsigned int k = 0; k < dim; ++k)
                          g[(vi * dim + k) * nv * nv + a * nv + b] += d[k];
                      }
                }
            }
        }
    Utilities::MPI::sum(g, m.comm, g);
    std::vector<std::array<SymmetricTensor<4, dim>, dim>> result(
      m.tria->n_vertices());
    for (unsigned int v = 0; v < result.size(); ++v)
      for (unsigned int k = 0; k < dim; ++k)
        for (unsigned int a = 0; a < nv; ++a)
          for (unsigned int b = a; b < nv; ++b)
            {
              const auto [i, j]        = voigt_pair<dim>(a);
              const auto [r, t]        = voigt_pair<dim>(b);
              result[v][k][i][j][r][t] = result[v][k][r][t][i][j] =
                g[(v * dim + k) * nv * nv + a * nv + b];
            }
    return result;
  }



  namespace
  {
    // DataOut whose patches are moved by x -> F x, with the first `n_vector`
    // dim-vectors of data mapped by F^-T.
    template <int dim>
    class MappedDataOut : public DataOut<dim>
    {
    public:
      MappedDataOut(const Tensor<2, dim> &F, const unsigned int n_vectors)
        : F(F)
        , n_vectors(n_vectors)
      {}

      void
      map_patches()
      {
        patches                  = DataOut<dim>::get_patches();
        const Tensor<2, dim> G_T = transpose(invert(F));
        for (auto &patch : patches)
          {
            for (auto &v : patch.vertices)
              v = Point<dim>(F * v);
            // Patches at the boundary carry their points in the last dim
            // rows of the data.
            if (patch.points_are_available)
              for (unsigned int q = 0; q < patch.data.size(1); ++q)
                {
                  Point<dim>         x;
                  const unsigned int first = patch.data.size(0) - dim;
                  for (unsigned int d = 0; d < dim; ++d)
                    x[d] = patch.data(first + d, q);
                  x = Point<dim>(F * x);
                  for (unsigned int d = 0; d < dim; ++d)
                    patch.data(first + d, q) = x[d];
                }
            for (unsigned int k = 0; k < n_vectors; ++k)
              for (unsigned int q = 0; q < patch.data.size(1); ++q)
                {
                  Tensor<1, dim> w;
                  for (unsigned int d = 0; d < dim; ++d)
                    w[d] = patch.data(k * dim + d, q);
                  w = G_T * w;
                  for (unsigned int d = 0; d < dim; ++d)
                    patch.data(k * dim + d, q) = w[d];
                }
          }
      }

      const std::vector<DataOutBase::Patch<dim, dim>> &
      get_patches() const override
      {
        return patches;
      }

    private:
      const Tensor<2, dim>                      F;
      const unsigned int                        n_vectors;
      std::vector<DataOutBase::Patch<dim, dim>> patches;
    };
  } // namespace



  template <int dim>
  void
  PeriodicHomogenization<dim>::write_vtu(
    const std::string              &file_stem,
    const std::vector<std::string> &cell_data_names,
    const std::function<std::vector<double>(const Point<dim> &,
                                            const types::material_id)>
                         &cell_data,
    const Tensor<2, dim> &F) const
  {
    const Impl &m = *impl;
    AssertThrow(m.fluctuation.size() == Impl::nv,
                ExcMessage("write_vtu() needs a homogenize() first"));
    MappedDataOut<dim> out(F, Impl::nv);
    out.attach_dof_handler(m.dof_handler);
    const std::vector<DataComponentInterpretation::DataComponentInterpretation>
      vector(dim, DataComponentInterpretation::component_is_part_of_vector);
    static const char *names2[3] = {"w_11", "w_22", "w_12"};
    static const char *names3[6] = {
      "w_11", "w_22", "w_33", "w_23", "w_13", "w_12"};
    for (unsigned int c = 0; c < Impl::nv; ++c)
      out.add_data_vector(
        m.fluctuation[c],
        std::vector<std::string>(dim, dim == 2 ? names2[c] : names3[c]),
        DataOut<dim>::type_dof_data,
        vector);
    std::vector<Vector<float>> data(cell_data_names.size(),
                                    Vector<float>(m.tria->n_active_cells()));
    for (const auto &cell : m.tria->active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const std::vector<double> v =
            cell_data(cell->center(), cell->material_id());
          for (unsigned int k = 0; k < data.size(); ++k)
            data[k][cell->active_cell_index()] = v.at(k);
        }
    for (unsigned int k = 0; k < data.size(); ++k)
      out.add_data_vector(data[k],
                          cell_data_names[k],
                          DataOut<dim>::type_cell_data);
    out.build_patches(*m.mapping);
    out.map_patches();
    const std::string directory =
      file_stem.find('/') == std::string::npos ?
        "./" :
        file_stem.substr(0, file_stem.rfind('/') + 1);
    const std::string name = file_stem.substr(directory.size());
    if (Utilities::MPI::n_mpi_processes(m.comm) == 1)
      {
        std::ofstream file(file_stem + ".vtu");
        AssertThrow(file, ExcMessage("cannot write '" + file_stem + ".vtu'"));
        out.write_vtu(file);
      }
    else
      out.write_vtu_with_pvtu_record(directory, name, 0, m.comm, 0, 0);
  }



  template <int dim>
  types::global_dof_index
  PeriodicHomogenization<dim>::n_dofs() const
  {
    return impl->dof_handler.n_dofs();
  }



  template <int dim>
  types::global_dof_index
  PeriodicHomogenization<dim>::n_unknowns() const
  {
    types::global_dof_index n = 0;
    for (const auto i : impl->owned)
      n += !impl->constraints.is_constrained(i);
    return Utilities::MPI::sum(n, impl->comm);
  }



  template <int dim>
  types::global_cell_index
  PeriodicHomogenization<dim>::n_cells() const
  {
    return impl->tria->n_global_active_cells();
  }



  template <int dim>
  double
  PeriodicHomogenization<dim>::volume() const
  {
    return impl->box_volume;
  }



  template class PeriodicHomogenization<2>;
  template class PeriodicHomogenization<3>;
} // namespace forma
