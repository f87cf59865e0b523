#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <forma/homogenization/grid_multigrid.h>
#include <forma/homogenization/periodic_homogenization.h>

#include "periodic_homogenization_impl.h"

// PeriodicHomogenization with Solver type "multigrid": regular 2D grids
// handed to GridMultigridHomogenization (no mesh, no matrix).

namespace forma
{
  using namespace dealii;

  template <int dim>
  void
  PeriodicHomogenization<dim>::Impl::setup_grid(
    const Point<dim>                    &size,
    const std::array<unsigned int, dim> &n_cells,
    const unsigned int                   degree)
  {
    AssertThrow(dim == 2 && degree == 1,
                ExcMessage("the multigrid solver is for 2D grids of Q1 "
                           "elements (use the direct or cg-amg solver)"));
    AssertThrow(lattice.shift.norm() == 0 && !lattice.inversion,
                ExcMessage("the multigrid solver homogenizes the whole "
                           "periodic box: no lattice shift or inversion "
                           "symmetry (Use symmetry = false)"));
    if constexpr (dim == 2)
      {
        GridMultigridHomogenization::Parameters p;
        p.tolerance = solver_parameters.tolerance;
        grid = std::make_unique<GridMultigridHomogenization>(size, n_cells, p);
      }
    grid_cells = n_cells;
    grid_size  = size;
    box_volume = 1;
    for (unsigned int d = 0; d < dim; ++d)
      box_volume *= size[d];
  }



  template <int dim>
  Point<dim>
  PeriodicHomogenization<dim>::Impl::pixel_center(const std::size_t p) const
  {
    Point<dim>  x;
    std::size_t rest = p;
    for (unsigned int d = 0; d < dim; ++d)
      {
        x[d] = (rest % grid_cells[d] + 0.5) * grid_size[d] / grid_cells[d];
        rest /= grid_cells[d];
      }
    return x;
  }



  template <int dim>
  typename PeriodicHomogenization<dim>::Result
  PeriodicHomogenization<dim>::Impl::homogenize_on_grid(
    const MaterialFunction &material)
  {
    Result result;
    if constexpr (dim == 2)
      {
        const auto r = grid->homogenize(
          [&](const std::size_t p) { return material(pixel_center(p), 0); });
        result.C = r.C;
        result.linear_iterations.assign(nv, r.iterations);
        result.solver = "multigrid";
      }
    (void)material;
    return result;
  }



  template <int dim>
  std::vector<SymmetricTensor<4, dim>>
  PeriodicHomogenization<dim>::Impl::material_gradient_on_grid(
    const MaterialDerivativeFunction &material_derivative,
    const unsigned int                n_parameters) const
  {
    std::vector<SymmetricTensor<4, dim>> gradient(n_parameters);
    if constexpr (dim == 2)
      {
        std::vector<std::vector<SymmetricTensor<4, 2>>> derivative(
          static_cast<std::size_t>(grid_cells[0]) * grid_cells[1]);
        for (std::size_t p = 0; p < derivative.size(); ++p)
          {
            derivative[p] = material_derivative(pixel_center(p), 0);
            AssertThrow(derivative[p].size() == n_parameters,
                        ExcMessage("material_gradient(): the material "
                                   "derivative has " +
                                   std::to_string(derivative[p].size()) +
                                   " entries, not " +
                                   std::to_string(n_parameters)));
          }
        gradient = grid->material_gradient(derivative);
        gradient.resize(n_parameters);
      }
    (void)material_derivative;
    return gradient;
  }



  template <int dim>
  void
  PeriodicHomogenization<dim>::Impl::write_vtu_on_grid(
    const std::string              &file_stem,
    const std::vector<std::string> &cell_data_names,
    const std::function<std::vector<double>(const Point<dim> &,
                                            const types::material_id)>
      &cell_data) const
  {
    if constexpr (dim == 2)
      {
        const std::size_t n =
          static_cast<std::size_t>(grid_cells[0]) * grid_cells[1];
        std::vector<std::vector<double>> data(cell_data_names.size(),
                                              std::vector<double>(n));
        for (std::size_t p = 0; p < n; ++p)
          {
            const std::vector<double> v = cell_data(pixel_center(p), 0);
            for (unsigned int k = 0; k < data.size(); ++k)
              data[k][p] = v.at(k);
          }
        // every process holds the whole grid: one writes it
        if (Utilities::MPI::this_mpi_process(comm) == 0)
          grid->write_vtu(file_stem, cell_data_names, data);
      }
    (void)file_stem;
    (void)cell_data_names;
    (void)cell_data;
  }



  // The members defined here, for both dimensions (the class itself is
  // instantiated in periodic_homogenization.cc).
#define FORMA_INSTANTIATE(dim)                                                \
  template void PeriodicHomogenization<dim>::Impl::setup_grid(                \
    const Point<dim> &, const std::array<unsigned int, dim> &, unsigned int); \
  template Point<dim> PeriodicHomogenization<dim>::Impl::pixel_center(        \
    std::size_t) const;                                                       \
  template PeriodicHomogenization<dim>::Result                                \
  PeriodicHomogenization<dim>::Impl::homogenize_on_grid(                      \
    const MaterialFunction &);                                                \
  template std::vector<SymmetricTensor<4, dim>>                               \
  PeriodicHomogenization<dim>::Impl::material_gradient_on_grid(               \
    const MaterialDerivativeFunction &, unsigned int) const;                  \
  template void PeriodicHomogenization<dim>::Impl::write_vtu_on_grid(         \
    const std::string &,                                                      \
    const std::vector<std::string> &,                                         \
    const std::function<std::vector<double>(const Point<dim> &,               \
                                            const types::material_id)> &)     \
    const;
  FORMA_INSTANTIATE(2)
  FORMA_INSTANTIATE(3)
#undef FORMA_INSTANTIATE
} // namespace forma
