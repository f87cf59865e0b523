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

#include "periodic_homogenization_impl.h"

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
  void
  PeriodicHomogenization<dim>::Impl::setup(const unsigned int degree,
                                           const Point<dim>  &box)
  {
    box_volume = 1;
    box_size   = box;
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
    if (refined)
      {
        // A refined grid: the level-0 pairs, whose refined faces
        // make_periodicity_constraints() follows down to the active ones
        // (p4est keeps both sides within one level).
        DoFTools::make_hanging_node_constraints(dof_handler, constraints);
        DoFTools::make_periodicity_constraints<dim, dim, double>(
          grid_face_pairs(dof_handler.cell_iterators_on_level(0),
                          box,
                          lattice.shift),
          constraints);
      }
    else if (congruent_cells)
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
            const types::global_dof_index i0 = cell->vertex_dof_index(v, 0);
            // A hanging vertex (refined grids) follows its neighbours.
            if (!interior || constraints.is_constrained(i0))
              continue;
            const double dist = cell->vertex(v).distance(center);
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
                           "' (auto | direct | cg-amg; multigrid on "
                           "regular 2D grids)"));
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



  namespace
  {
    /// Meshes have no pixel grid: "multigrid" means auto there.
    template <typename SolverParameters>
    SolverParameters
    for_mesh(SolverParameters solver)
    {
      if (solver.type == "multigrid")
        solver.type = "auto";
      return solver;
    }
  } // namespace



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
    impl->lattice = lattice;
    if (solver.type == "multigrid")
      {
        impl->setup_grid(size, n_cells, degree);
        return;
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
    : impl(std::make_unique<Impl>(comm, for_mesh(solver)))
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
    : impl(std::make_unique<Impl>(comm, for_mesh(solver)))
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
  types::global_dof_index
  PeriodicHomogenization<dim>::n_dofs() const
  {
    if (impl->grid)
      return dim * n_cells();
    return impl->dof_handler.n_dofs();
  }



  template <int dim>
  types::global_dof_index
  PeriodicHomogenization<dim>::n_unknowns() const
  {
    if (impl->grid) // the periodic nodes, one of them fixed
      return dim * (n_cells() - 1);
    types::global_dof_index n = 0;
    for (const auto i : impl->owned)
      n += !impl->constraints.is_constrained(i);
    return Utilities::MPI::sum(n, impl->comm);
  }



  template <int dim>
  types::global_cell_index
  PeriodicHomogenization<dim>::n_cells() const
  {
    if (impl->grid)
      {
        types::global_cell_index n = 1;
        for (const unsigned int c : impl->grid_cells)
          n *= c;
        return n;
      }
    return impl->tria->n_global_active_cells();
  }



  template <int dim>
  double
  PeriodicHomogenization<dim>::volume() const
  {
    return impl->box_volume;
  }



  template struct PeriodicHomogenization<2>::Impl;
  template struct PeriodicHomogenization<3>::Impl;
  template class PeriodicHomogenization<2>;
  template class PeriodicHomogenization<3>;
} // namespace forma
