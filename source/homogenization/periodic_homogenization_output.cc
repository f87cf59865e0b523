#include <deal.II/numerics/data_out.h>

#include <forma/homogenization/periodic_homogenization.h>

#include "periodic_homogenization_impl.h"

#include <fstream>

// PeriodicHomogenization::write_vtu(): the fluctuations and cell data.

namespace forma
{
  using namespace dealii;

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
    if (impl->grid)
      {
        AssertThrow((F == Tensor<2, dim>(unit_symmetric_tensor<dim>())),
                    ExcMessage("write_vtu(): the multigrid solver's grid "
                               "is a box, not a mapped cell"));
        impl->write_vtu_on_grid(file_stem, cell_data_names, cell_data);
        return;
      }
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


  template void
  PeriodicHomogenization<2>::write_vtu(
    const std::string &,
    const std::vector<std::string> &,
    const std::function<std::vector<double>(const Point<2> &,
                                            const types::material_id)> &) const;
  template void
  PeriodicHomogenization<2>::write_vtu(
    const std::string &,
    const std::vector<std::string> &,
    const std::function<std::vector<double>(const Point<2> &,
                                            const types::material_id)> &,
    const Tensor<2, 2> &) const;
  template void
  PeriodicHomogenization<3>::write_vtu(
    const std::string &,
    const std::vector<std::string> &,
    const std::function<std::vector<double>(const Point<3> &,
                                            const types::material_id)> &) const;
  template void
  PeriodicHomogenization<3>::write_vtu(
    const std::string &,
    const std::vector<std::string> &,
    const std::function<std::vector<double>(const Point<3> &,
                                            const types::material_id)> &,
    const Tensor<2, 3> &) const;
} // namespace forma
