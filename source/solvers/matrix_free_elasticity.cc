#include <deal.II/base/subscriptor.h>
#include <deal.II/base/timer.h>
#include <deal.II/base/vectorization.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/hp/mapping_collection.h>
#include <deal.II/lac/diagonal_matrix.h>
#include <deal.II/lac/la_parallel_vector.h>
#include <deal.II/lac/precondition.h>
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/solver_gmres.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_sparsity_pattern.h>
#include <deal.II/matrix_free/fe_evaluation.h>
#include <deal.II/matrix_free/matrix_free.h>
#include <deal.II/matrix_free/tools.h>
#include <deal.II/multigrid/mg_transfer_global_coarsening.h>

#include <forma/physics/material.h>
#include <forma/solvers/matrix_free_elasticity.h>
#include <forma/solvers/rigid_body_modes.h>

#include <array>
#include <atomic>
#include <functional>
#include <optional>

namespace forma
{
  using namespace dealii;

  namespace
  {
    using VectorType = LinearAlgebra::distributed::Vector<double>;
    using VA         = VectorizedArray<double>;

    /// Tangents of one cell batch at its quadrature points; stride 0: the
    /// same at every point; no source: no zeroth-order term. `lame`
    /// (lambda, mu) in place of `flux`: the isotropic tangent
    /// lambda I x I + 2 mu sym, the same at every point.
    template <int dim>
    struct BatchTangent
    {
      const Tensor<4, dim, VA> *flux          = nullptr;
      unsigned int              flux_stride   = 0;
      const VA                 *source        = nullptr;
      unsigned int              source_stride = 0;
      const VA                 *lame          = nullptr;
    };

    /// (lambda, mu) if A = lambda I x I + mu (d_ik d_jl + d_il d_jk) to
    /// round-off (linear isotropic elasticity), else nothing.
    template <int dim>
    std::optional<std::array<double, 2>>
    isotropic_moduli(const Tensor<4, dim> &A)
    {
      const double lambda = A[0][0][1][1], mu = A[0][1][0][1];
      if ((A - isotropic_tangent<dim>(lambda, mu)).norm() <= 1e-13 * A.norm())
        return std::array<double, 2>{{lambda, mu}};
      return {};
    }

    /// phi <- the cell integral of (A : grad u, grad v) + (s u, v) for the
    /// DoF values in phi: the Jacobian of the forms' flux and source.
    template <int dim, typename Evaluator>
    void
    apply_tangent(Evaluator &phi, const BatchTangent<dim> &t)
    {
      const EvaluationFlags::EvaluationFlags flags =
        t.source ? EvaluationFlags::values | EvaluationFlags::gradients :
                   EvaluationFlags::gradients;
      phi.evaluate(flags);
      for (unsigned int q = 0; q < phi.n_q_points; ++q)
        {
          const Tensor<2, dim, VA> g = phi.get_gradient(q);
          Tensor<2, dim, VA>       f;
          if (t.lame)
            {
              // lambda tr(g) I + mu (g + g^T): a tenth of the work of the
              // general contraction below.
              const VA lambda_trace = dealii::trace(g) * t.lame[0];
              for (unsigned int i = 0; i < dim; ++i)
                {
                  for (unsigned int J = 0; J < dim; ++J)
                    f[i][J] = t.lame[1] * (g[i][J] + g[J][i]);
                  f[i][i] += lambda_trace;
                }
            }
          else
            {
              const Tensor<4, dim, VA> &A = t.flux[q * t.flux_stride];
              for (unsigned int i = 0; i < dim; ++i)
                for (unsigned int J = 0; J < dim; ++J)
                  for (unsigned int k = 0; k < dim; ++k)
                    for (unsigned int l = 0; l < dim; ++l)
                      f[i][J] += A[i][J][k][l] * g[k][l];
            }
          phi.submit_gradient(f, q);
          if (t.source)
            phi.submit_value(t.source[q * t.source_stride] * phi.get_value(q),
                             q);
        }
      phi.integrate(flags);
    }
  } // namespace



  template <int dim>
  struct MatrixFreeElasticity<dim>::Impl
  {
    /// The Q_p operator as CG, GMRES and Chebyshev see it (no Tvmult: an
    /// adjoint sets transposed tangents instead).
    struct Operator : public Subscriptor
    {
      explicit Operator(const Impl *impl)
        : impl(impl)
      {}
      const Impl *impl;
      void
      vmult(VectorType &dst, const VectorType &src) const
      {
        impl->apply(dst, src);
      }
      void
      initialize_dof_vector(VectorType &v) const
      {
        impl->mf.initialize_dof_vector(v);
      }
      types::global_dof_index
      m() const
      {
        return impl->dofs.n_dofs();
      }
      /// Diagonal entries (Chebyshev asks when it has no preconditioner).
      double
      el(const types::global_dof_index i, const types::global_dof_index j) const
      {
        AssertThrow(i == j, ExcNotImplemented());
        return 1. / impl->inverse_diagonal->get_vector()(i);
      }
    };

    /// One symmetric two-level V-cycle: Chebyshev, AMG on Q1, Chebyshev.
    struct TwoLevel
    {
      const Impl *impl;
      void
      vmult(VectorType &dst, const VectorType &src) const
      {
        impl->v_cycle(dst, src);
      }
    };

    using Smoother =
      PreconditionChebyshev<Operator, VectorType, DiagonalMatrix<VectorType>>;

    explicit Impl(const LinearSolver::Parameters &p)
      : parameters(p)
    {}

    void
    build_constraints(const DoFHandler<dim>           &caller,
                      const AffineConstraints<double> &caller_constraints);
    void
    build_index_map(const DoFHandler<dim> &caller);
    /// The batch's tangents appended to `flux` and `source`, or to `lame`
    /// when every lane's is isotropic; returns whether it was.
    bool
    gather(const MatrixFree<dim, double>   &data,
           const unsigned int               batch,
           std::vector<Tensor<4, dim, VA>> &flux,
           std::vector<VA>                 &source,
           std::vector<VA>                 &lame) const;
    /// The tangent of a cell at point q.
    Tensor<4, dim>
    cell_tangent(const unsigned int cell, const unsigned int q) const;
    bool
    has_tangent(const unsigned int cell) const
    {
      return !cell_flux[cell].empty() || cell_lame[cell];
    }
    void
    setup_preconditioner();
    void
    compute_inverse_diagonal(VectorType &inverse) const;
    template <int degree>
    void
    local_apply(const MatrixFree<dim, double>               &data,
                VectorType                                  &dst,
                const VectorType                            &src,
                const std::pair<unsigned int, unsigned int> &range) const;
    template <int degree>
    void
    setup_degree();
    void
    apply(VectorType &dst, const VectorType &src) const;
    void
    v_cycle(VectorType &dst, const VectorType &src) const;

    BatchTangent<dim>
    batch_tangent(const unsigned int b) const
    {
      return {batch_flux.data() + flux_offset[b],
              flux_stride[b],
              has_source ? &batch_source[source_offset[b]] : nullptr,
              source_stride[b],
              lame_offset[b] == numbers::invalid_unsigned_int ?
                nullptr :
                &batch_lame[lame_offset[b]]};
    }

    const LinearSolver::Parameters parameters;
    const Mapping<dim>            *mapping = nullptr;
    unsigned int                   degree  = 0;
    DoFHandler<dim>                dofs, dofs_q1;
    AffineConstraints<double>      constraints, constraints_q1;
    MatrixFree<dim, double>        mf, mf_q1;
    /// Index in `dofs` of each DoF the caller owns (by index within set).
    IndexSet                             caller_owned;
    std::vector<types::global_dof_index> own_index;

    std::vector<std::vector<Tensor<4, dim>>> cell_flux;
    /// Isotropic cells keep (lambda, mu) here instead of a cell_flux entry.
    std::vector<std::optional<std::array<double, 2>>> cell_lame;
    std::vector<std::vector<double>>                  cell_source;
    std::atomic<bool>                                 tangent_changed{true};
    std::atomic<bool>                                 unsymmetric{false};

    std::vector<Tensor<4, dim, VA>> batch_flux;
    std::vector<VA>                 batch_source;
    std::vector<VA>                 batch_lame;
    std::vector<unsigned int>       flux_offset, flux_stride, lame_offset;
    std::vector<unsigned int>       source_offset, source_stride;
    bool                            has_source = false;

    std::function<void(VectorType &, const VectorType &)> apply_cells;
    Operator                                              op{this};
    std::shared_ptr<DiagonalMatrix<VectorType>>           inverse_diagonal;
    Smoother                                              smoother;
    MGTwoLevelTransfer<dim, VectorType>                   transfer;
    TrilinosWrappers::SparseMatrix                        matrix_q1;
    TrilinosWrappers::PreconditionAMG                     amg;
    mutable VectorType residual, coarse_residual, coarse_correction, correction;
    double             setup_seconds = 0, solve_seconds = 0;
  };



  template <int dim>
  void
  MatrixFreeElasticity<dim>::Impl::build_constraints(
    const DoFHandler<dim>           &caller,
    const AffineConstraints<double> &caller_constraints)
  {
    // Own hanging-node constraints; Dirichlet rows copied from the caller's
    // (a row without entries), for Q1 at the vertices: FESystem numbers
    // the vertex DoFs first and alike for every degree.
    const unsigned int n_vertex_dofs =
      dim * GeometryInfo<dim>::vertices_per_cell;
    for (auto *c : {&constraints, &constraints_q1})
      c->clear();
    constraints.reinit(DoFTools::extract_locally_relevant_dofs(dofs));
    constraints_q1.reinit(DoFTools::extract_locally_relevant_dofs(dofs_q1));
    DoFTools::make_hanging_node_constraints(dofs, constraints);
    DoFTools::make_hanging_node_constraints(dofs_q1, constraints_q1);

    std::vector<types::global_dof_index> a, b, b1;
    auto own = dofs.begin_active(), own_q1 = dofs_q1.begin_active();
    for (const auto &cell : caller.active_cell_iterators())
      {
        if (!cell->is_artificial())
          {
            a.resize(cell->get_fe().n_dofs_per_cell());
            b.resize(a.size());
            b1.resize(n_vertex_dofs);
            cell->get_dof_indices(a);
            own->get_dof_indices(b);
            own_q1->get_dof_indices(b1);
            for (unsigned int i = 0; i < a.size(); ++i)
              {
                const auto *entries =
                  caller_constraints.get_constraint_entries(a[i]);
                if (entries == nullptr || !entries->empty())
                  continue;
                if (!constraints.is_constrained(b[i]))
                  constraints.add_line(b[i]);
                if (i < n_vertex_dofs && !constraints_q1.is_constrained(b1[i]))
                  constraints_q1.add_line(b1[i]);
              }
          }
        ++own;
        ++own_q1;
      }
    constraints.close();
    constraints_q1.close();
  }



  template <int dim>
  void
  MatrixFreeElasticity<dim>::Impl::build_index_map(
    const DoFHandler<dim> &caller)
  {
    caller_owned = caller.locally_owned_dofs();
    own_index.assign(caller_owned.n_elements(), numbers::invalid_dof_index);
    std::vector<types::global_dof_index> a, b;
    auto                                 own = dofs.begin_active();
    for (const auto &cell : caller.active_cell_iterators())
      {
        if (cell->is_locally_owned())
          {
            a.resize(cell->get_fe().n_dofs_per_cell());
            b.resize(a.size());
            cell->get_dof_indices(a);
            own->get_dof_indices(b);
            for (unsigned int i = 0; i < a.size(); ++i)
              if (caller_owned.is_element(a[i]))
                own_index[caller_owned.index_within_set(a[i])] = b[i];
          }
        ++own;
      }
    // Same owners in both numberings (p4est's rule, same element):
    // checked on every rank together, so no rank waits for one that threw.
    bool same =
      dofs.locally_owned_dofs().n_elements() == caller_owned.n_elements();
    for (const auto i : own_index)
      same &= dofs.locally_owned_dofs().is_element(i);
    AssertThrow(Utilities::MPI::min(same ? 1u : 0u, dofs.get_communicator()) ==
                  1u,
                ExcMessage("matrix-free solver: the DoFs are owned "
                           "differently from the caller's."));
  }



  template <int dim>
  Tensor<4, dim>
  MatrixFreeElasticity<dim>::Impl::cell_tangent(const unsigned int cell,
                                                const unsigned int q) const
  {
    if (const auto &m = cell_lame[cell])
      return isotropic_tangent<dim>((*m)[0], (*m)[1]);
    const auto &c = cell_flux[cell];
    return c[c.size() == 1 ? 0 : q];
  }



  template <int dim>
  bool
  MatrixFreeElasticity<dim>::Impl::gather(const MatrixFree<dim, double> &data,
                                          const unsigned int             batch,
                                          std::vector<Tensor<4, dim, VA>> &flux,
                                          std::vector<VA> &source,
                                          std::vector<VA> &lame) const
  {
    // The cells of the batch's lanes (empty lanes repeat the first), then
    // (lambda, mu) if every lane's tangent is isotropic, else one tangent
    // per point, or one for all if every lane's is constant.
    const unsigned int n_lanes = data.n_active_entries_per_cell_batch(batch);
    std::array<unsigned int, VA::size()> cell;
    bool                                 isotropic = true;
    for (unsigned int v = 0; v < VA::size(); ++v)
      {
        cell[v] = data.get_cell_iterator(batch, v < n_lanes ? v : 0)
                    ->active_cell_index();
        Assert(has_tangent(cell[v]), ExcInternalError());
        isotropic &= cell_lame[cell[v]].has_value();
      }
    if (isotropic)
      for (unsigned int k = 0; k < 2; ++k)
        {
          VA m;
          for (unsigned int v = 0; v < VA::size(); ++v)
            m[v] = (*cell_lame[cell[v]])[k];
          lame.push_back(m);
        }
    const auto entries = [&](const auto &per_cell) {
      unsigned int n = 1;
      for (unsigned int v = 0; v < VA::size(); ++v)
        n = std::max<unsigned int>(n, per_cell[cell[v]].size());
      return n;
    };
    const unsigned int n_flux = isotropic ? 0 : entries(cell_flux);
    for (unsigned int q = 0; q < n_flux; ++q)
      {
        Tensor<4, dim, VA> A;
        for (unsigned int v = 0; v < VA::size(); ++v)
          {
            const Tensor<4, dim> a = cell_tangent(cell[v], q);
            for (unsigned int i = 0;
                 i < Tensor<4, dim>::n_independent_components;
                 ++i)
              {
                const auto index =
                  Tensor<4, dim>::unrolled_to_component_indices(i);
                A[index][v] = a[index];
              }
          }
        flux.push_back(A);
      }
    if (!has_source)
      return isotropic;
    const unsigned int n_source = entries(cell_source);
    for (unsigned int q = 0; q < n_source; ++q)
      {
        VA s = 0.;
        for (unsigned int v = 0; v < VA::size(); ++v)
          {
            const auto &c = cell_source[cell[v]];
            s[v]          = c.empty() ? 0. : c[c.size() == 1 ? 0 : q];
          }
        source.push_back(s);
      }
    return isotropic;
  }



  template <int dim>
  template <int degree>
  void
  MatrixFreeElasticity<dim>::Impl::local_apply(
    const MatrixFree<dim, double>               &data,
    VectorType                                  &dst,
    const VectorType                            &src,
    const std::pair<unsigned int, unsigned int> &range) const
  {
    FEEvaluation<dim, degree, degree + 1, dim, double> phi(data);
    for (unsigned int b = range.first; b < range.second; ++b)
      {
        phi.reinit(b);
        phi.read_dof_values(src);
        apply_tangent<dim>(phi, batch_tangent(b));
        phi.distribute_local_to_global(dst);
      }
  }



  template <int dim>
  void
  MatrixFreeElasticity<dim>::Impl::apply(VectorType       &dst,
                                         const VectorType &src) const
  {
    apply_cells(dst, src);
    // Constrained rows are the identity: CG and Chebyshev leave them alone.
    for (const unsigned int i : mf.get_constrained_dofs())
      dst.local_element(i) = src.local_element(i);
  }



  template <int dim>
  void
  MatrixFreeElasticity<dim>::Impl::v_cycle(VectorType       &dst,
                                           const VectorType &src) const
  {
    // x = S b; x += P A1^-1 R (b - A x); x += S (b - A x), with S the
    // Chebyshev smoother and A1^-1 one AMG cycle: symmetric, as CG needs.
    smoother.vmult(dst, src);
    apply(residual, dst);
    residual.sadd(-1., 1., src);
    coarse_residual = 0.;
    transfer.restrict_and_add(coarse_residual, residual);
    amg.vmult(coarse_correction, coarse_residual);
    transfer.prolongate_and_add(dst, coarse_correction);
    apply(residual, dst);
    residual.sadd(-1., 1., src);
    smoother.vmult(correction, residual);
    dst += correction;
  }



  template <int dim>
  void
  MatrixFreeElasticity<dim>::Impl::compute_inverse_diagonal(
    VectorType &inverse) const
  {
    // Cell by cell with FEValues: a few times cheaper than a matrix-free
    // pass per column. Hanging-node couplings are left out of the
    // masters' entries, which only the smoother sees.
    mf.initialize_dof_vector(inverse);
    const FiniteElement<dim>            &fe = dofs.get_fe();
    FEValues<dim>                        fv(*mapping,
                     fe,
                     QGauss<dim>(degree + 1),
                     update_values | update_gradients | update_JxW_values);
    std::vector<types::global_dof_index> indices(fe.n_dofs_per_cell());
    for (const auto &cell : dofs.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fv.reinit(cell);
          cell->get_dof_indices(indices);
          const unsigned int index  = cell->active_cell_index();
          const auto        &source = cell_source[index];
          const auto        &lame   = cell_lame[index];
          const auto        &flux   = cell_flux[index];
          for (unsigned int i = 0; i < indices.size(); ++i)
            {
              if (constraints.is_constrained(indices[i]))
                continue;
              const unsigned int c = fe.system_to_component_index(i).first;
              double             d = 0;
              for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
                {
                  const auto &g = fv.shape_grad(i, q);
                  double      a = 0;
                  if (lame) // A_cJcL g_J g_L, A isotropic
                    a = ((*lame)[0] + (*lame)[1]) * g[c] * g[c] +
                        (*lame)[1] * g.norm_square();
                  else
                    {
                      const auto &A = flux[flux.size() == 1 ? 0 : q];
                      for (unsigned int J = 0; J < dim; ++J)
                        for (unsigned int L = 0; L < dim; ++L)
                          a += A[c][J][c][L] * g[J] * g[L];
                    }
                  if (!source.empty())
                    a += source[source.size() == 1 ? 0 : q] *
                         fv.shape_value(i, q) * fv.shape_value(i, q);
                  d += a * fv.JxW(q);
                }
              inverse(indices[i]) += d;
            }
        }
    inverse.compress(VectorOperation::add);
    for (unsigned int i = 0; i < inverse.locally_owned_size(); ++i)
      inverse.local_element(i) =
        inverse.local_element(i) > 0. ? 1. / inverse.local_element(i) : 1.;
  }



  template <int dim>
  template <int degree>
  void
  MatrixFreeElasticity<dim>::Impl::setup_degree()
  {
    apply_cells = [this](VectorType &dst, const VectorType &src) {
      mf.cell_loop(&Impl::local_apply<degree>, this, dst, src, true);
    };

    // Jacobi-Chebyshev smoother on Q_p.
    inverse_diagonal = std::make_shared<DiagonalMatrix<VectorType>>();
    compute_inverse_diagonal(inverse_diagonal->get_vector());
    typename Smoother::AdditionalData data;
    data.smoothing_range     = 20.;
    data.degree              = 4;
    data.eig_cg_n_iterations = 12;
    data.preconditioner      = inverse_diagonal;
    smoother.initialize(op, data);

    // Q1 from the same tangents at the same points.
    std::vector<Tensor<4, dim, VA>> flux;
    std::vector<VA>                 source, lame;
    unsigned int                    gathered  = numbers::invalid_unsigned_int;
    bool                            isotropic = false;
    MatrixFreeTools::compute_matrix<dim, 1, degree + 1, dim, double, VA>(
      mf_q1,
      constraints_q1,
      matrix_q1,
      [&](FEEvaluation<dim, 1, degree + 1, dim, double> &phi) {
        // Called once per column of a batch: gather when the batch changes.
        if (phi.get_current_cell_index() != gathered)
          {
            gathered = phi.get_current_cell_index();
            flux.clear();
            source.clear();
            lame.clear();
            isotropic = gather(mf_q1, gathered, flux, source, lame);
          }
        apply_tangent<dim>(phi,
                           {flux.data(),
                            flux.size() == 1 ? 0u : 1u,
                            has_source ? source.data() : nullptr,
                            source.size() == 1 ? 0u : 1u,
                            isotropic ? lame.data() : nullptr});
      });
  }



  template <int dim>
  void
  MatrixFreeElasticity<dim>::Impl::setup_preconditioner()
  {
    Timer timer;
    bool  complete = true;
    for (const auto &cell : dofs.active_cell_iterators())
      if (cell->is_locally_owned())
        complete &= has_tangent(cell->active_cell_index());
    AssertThrow(Utilities::MPI::min(complete ? 1u : 0u,
                                    dofs.get_communicator()) == 1u,
                ExcMessage("matrix-free solver: a cell has no tangent "
                           "(set_cell_tangent() not called for it)."));
    has_source = false;
    for (const auto &s : cell_source)
      has_source |= !s.empty();
    has_source =
      Utilities::MPI::logical_or(has_source, dofs.get_communicator());

    batch_flux.clear();
    batch_source.clear();
    batch_lame.clear();
    const unsigned int n_batches = mf.n_cell_batches();
    flux_offset.resize(n_batches);
    flux_stride.resize(n_batches);
    lame_offset.resize(n_batches);
    source_offset.resize(n_batches);
    source_stride.resize(n_batches);
    for (unsigned int b = 0; b < n_batches; ++b)
      {
        flux_offset[b]   = batch_flux.size();
        source_offset[b] = batch_source.size();
        lame_offset[b]   = batch_lame.size();
        if (!gather(mf, b, batch_flux, batch_source, batch_lame))
          lame_offset[b] = numbers::invalid_unsigned_int;
        flux_stride[b]   = batch_flux.size() - flux_offset[b] == 1 ? 0 : 1;
        source_stride[b] = batch_source.size() - source_offset[b] == 1 ? 0 : 1;
      }

    amg.clear(); // the old hierarchy points into the old matrix
    matrix_q1.clear();
    TrilinosWrappers::SparsityPattern sp(
      dofs_q1.locally_owned_dofs(),
      dofs_q1.locally_owned_dofs(),
      DoFTools::extract_locally_relevant_dofs(dofs_q1),
      dofs_q1.get_communicator());
    DoFTools::make_sparsity_pattern(dofs_q1,
                                    sp,
                                    constraints_q1,
                                    false,
                                    Utilities::MPI::this_mpi_process(
                                      dofs_q1.get_communicator()));
    sp.compress();
    matrix_q1.reinit(sp);

    switch (degree)
      {
        case 2:
          setup_degree<2>();
          break;
        case 3:
          setup_degree<3>();
          break;
        default:
          setup_degree<4>();
      }

    const RigidBodyModes modes =
      rigid_body_modes(hp::MappingCollection<dim>(*mapping), dofs_q1);
    initialize_elasticity_amg(
      amg, matrix_q1, modes.modes, false, modes.pde_equations);
    tangent_changed = false;
    setup_seconds   = timer.wall_time();
  }



  template <int dim>
  MatrixFreeElasticity<dim>::MatrixFreeElasticity(
    const LinearSolver::Parameters &parameters)
    : impl(std::make_unique<Impl>(parameters))
  {}



  template <int dim>
  MatrixFreeElasticity<dim>::~MatrixFreeElasticity() = default;



  template <int dim>
  void
  MatrixFreeElasticity<dim>::reinit(
    const Mapping<dim>              &mapping,
    const DoFHandler<dim>           &dof_handler,
    const AffineConstraints<double> &zero_constraints,
    const unsigned int               degree)
  {
    AssertThrow(degree >= 2 && degree <= 4,
                ExcMessage("Solver/Linear solver = cg-mg needs Finite element/"
                           "Degree 2, 3 or 4 (got " +
                           std::to_string(degree) +
                           "); for degree 1 use cg-amg."));
    AssertThrow(
      dof_handler.get_triangulation().all_reference_cells_are_hyper_cube(),
      ExcMessage("Solver/Linear solver = cg-mg needs a quadrilateral or "
                 "hexahedral mesh; on simplices use cg-amg."));
    Impl &m   = *impl;
    m.mapping = &mapping;
    m.degree  = degree;
    m.dofs.reinit(dof_handler.get_triangulation());
    m.dofs.distribute_dofs(FESystem<dim>(FE_Q<dim>(degree), dim));
    m.dofs_q1.reinit(dof_handler.get_triangulation());
    m.dofs_q1.distribute_dofs(FESystem<dim>(FE_Q<dim>(1), dim));
    m.build_constraints(dof_handler, zero_constraints);
    m.build_index_map(dof_handler);

    typename MatrixFree<dim, double>::AdditionalData data;
    data.tasks_parallel_scheme = MatrixFree<dim, double>::AdditionalData::none;
    data.mapping_update_flags =
      update_values | update_gradients | update_JxW_values;
    m.mf.reinit(mapping, m.dofs, m.constraints, QGauss<1>(degree + 1), data);
    m.mf_q1.reinit(
      mapping, m.dofs_q1, m.constraints_q1, QGauss<1>(degree + 1), data);
    m.transfer.reinit_polynomial_transfer(m.dofs,
                                          m.dofs_q1,
                                          m.constraints,
                                          m.constraints_q1);
    m.mf.initialize_dof_vector(m.residual);
    m.mf.initialize_dof_vector(m.correction);
    m.mf_q1.initialize_dof_vector(m.coarse_residual);
    m.mf_q1.initialize_dof_vector(m.coarse_correction);
    m.cell_flux.assign(dof_handler.get_triangulation().n_active_cells(), {});
    m.cell_source.assign(m.cell_flux.size(), {});
    m.cell_lame.assign(m.cell_flux.size(), {});
    m.tangent_changed = true;
    m.unsymmetric     = false;
  }



  namespace
  {
    /// A^T: the Jacobian's transpose swaps the (i, J) and (k, l) pairs.
    template <int dim>
    Tensor<4, dim>
    transposed(const Tensor<4, dim> &A)
    {
      Tensor<4, dim> T;
      for (unsigned int i = 0; i < dim; ++i)
        for (unsigned int J = 0; J < dim; ++J)
          for (unsigned int k = 0; k < dim; ++k)
            for (unsigned int l = 0; l < dim; ++l)
              T[i][J][k][l] = A[k][l][i][J];
      return T;
    }
  } // namespace



  template <int dim>
  void
  MatrixFreeElasticity<dim>::set_cell_tangent(
    const unsigned int                 active_cell_index,
    const std::vector<Tensor<4, dim>> &flux_tangent,
    const std::vector<double>         &source_tangent,
    const bool                         transpose)
  {
    // One entry where the tangent is the same at every point (linear
    // elasticity), which is what keeps the memory low.
    const auto compact = [](const auto &values) {
      for (const auto &v : values)
        if (!(v == values[0]))
          return values;
      return std::decay_t<decltype(values)>(values.begin(),
                                            values.begin() +
                                              (values.empty() ? 0 : 1));
    };
    auto &flux = impl->cell_flux[active_cell_index];
    flux       = compact(flux_tangent);
    for (auto &A : flux)
      {
        const Tensor<4, dim> T = transposed(A);
        if (!impl->unsymmetric && (A - T).norm() > 1e-12 * A.norm())
          impl->unsymmetric = true;
        if (transpose)
          A = T;
      }
    // An isotropic cell keeps two numbers instead of 81 (3D).
    auto &lame = impl->cell_lame[active_cell_index];
    lame       = flux.size() == 1 ? isotropic_moduli(flux[0]) :
                                    std::optional<std::array<double, 2>>();
    if (lame)
      std::vector<Tensor<4, dim>>().swap(flux);
    bool any_source = false;
    for (const double s : source_tangent)
      any_source |= (s != 0.);
    impl->cell_source[active_cell_index] =
      any_source ? compact(source_tangent) : std::vector<double>();
    impl->tangent_changed = true;
  }



  template <int dim>
  unsigned int
  MatrixFreeElasticity<dim>::solve(TrilinosWrappers::MPI::Vector       &x,
                                   const TrilinosWrappers::MPI::Vector &b)
  {
    Impl &m = *impl;
    // Collective: a rank without cells sets no tangent but must take part.
    if (Utilities::MPI::logical_or(m.tangent_changed.load(),
                                   m.dofs.get_communicator()))
      m.setup_preconditioner();
    Timer      timer;
    VectorType own_x, own_b;
    m.mf.initialize_dof_vector(own_x);
    m.mf.initialize_dof_vector(own_b);
    unsigned int k = 0;
    for (const auto i : m.caller_owned)
      own_b[m.own_index[k++]] = b[i];
    SolverControl control(m.parameters.max_iterations,
                          m.parameters.relative_tolerance * own_b.l2_norm(),
                          false,
                          false);
    const bool    unsymmetric =
      Utilities::MPI::logical_or(m.unsymmetric.load(),
                                 m.dofs.get_communicator());
    try
      {
        const typename Impl::TwoLevel preconditioner{&m};
        if (unsymmetric)
          {
            // Right preconditioning: the stopping test sees the true
            // residual, as CG's does (left: the preconditioned one).
            SolverGMRES<VectorType> gmres(
              control,
              typename SolverGMRES<VectorType>::AdditionalData(100, true));
            gmres.solve(m.op, own_x, own_b, preconditioner);
          }
        else
          {
            SolverCG<VectorType> cg(control);
            cg.solve(m.op, own_x, own_b, preconditioner);
          }
      }
    catch (const SolverControl::NoConvergence &exc)
      {
        AssertThrow(false,
                    ExcMessage(no_convergence_message(unsymmetric ?
                                                        "cg-mg (GMRES)" :
                                                        "cg-mg (CG)",
                                                      exc.last_step,
                                                      exc.last_residual)));
      }
    k = 0;
    for (const auto i : m.caller_owned)
      x[i] = own_x[m.own_index[k++]];
    x.compress(VectorOperation::insert);
    m.solve_seconds = timer.wall_time();
    return control.last_step();
  }



  template <int dim>
  std::pair<double, double>
  MatrixFreeElasticity<dim>::last_times() const
  {
    return {impl->setup_seconds, impl->solve_seconds};
  }



  template class MatrixFreeElasticity<2>;
  template class MatrixFreeElasticity<3>;
} // namespace forma
