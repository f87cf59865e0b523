#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_values.h>

#include <forma/homogenization/periodic_homogenization.h>

#include "periodic_homogenization_impl.h"

// Derivatives of C^H: with respect to the cell material (material_gradient)
// and to the mesh's vertices (vertex_shape_gradient); neither needs an
// adjoint solve.

namespace forma
{
  using namespace dealii;

  template <int dim>
  std::vector<SymmetricTensor<4, dim>>
  PeriodicHomogenization<dim>::material_gradient(
    const MaterialDerivativeFunction &material_derivative,
    const unsigned int                n_parameters) const
  {
    if (impl->grid)
      return impl->material_gradient_on_grid(material_derivative, n_parameters);
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
    AssertThrow(!impl->grid,
                ExcMessage("vertex_shape_gradient() is for cell meshes, not "
                           "the multigrid solver's pixel grid"));
    const Impl        &m  = *impl;
    constexpr unsigned nv = Impl::nv;
    AssertThrow(m.fluctuation.size() == nv,
                ExcMessage("vertex_shape_gradient() needs a homogenize() "
                           "first"));
    AssertThrow(!m.congruent_cells || !m.lattice.inversion,
                ExcMessage("vertex_shape_gradient() is for cell meshes"));
    AssertThrow(!m.refined,
                ExcMessage("vertex_shape_gradient() is for cell meshes "
                           "without hanging vertices, not refined grids"));
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


  template std::vector<SymmetricTensor<4, 2>>
  PeriodicHomogenization<2>::material_gradient(
    const MaterialDerivativeFunction &,
    const unsigned int) const;
  template std::vector<std::array<SymmetricTensor<4, 2>, 2>>
  PeriodicHomogenization<2>::vertex_shape_gradient() const;
  template std::vector<SymmetricTensor<4, 3>>
  PeriodicHomogenization<3>::material_gradient(
    const MaterialDerivativeFunction &,
    const unsigned int) const;
  template std::vector<std::array<SymmetricTensor<4, 3>, 3>>
  PeriodicHomogenization<3>::vertex_shape_gradient() const;
} // namespace forma
