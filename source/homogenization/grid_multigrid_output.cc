#include <deal.II/base/exceptions.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>
#include <deal.II/numerics/data_out.h>

#include "grid_multigrid_impl.h"

#include <fstream>

// GridMultigridHomogenization::write_vtu(): the pixel grid as a deal.II
// mesh, with the fluctuations on its vertices (periodic: the last row and
// column repeat the first) and the cell data on its cells.

namespace forma
{
  using namespace dealii;
  using namespace internal::grid_multigrid;

  void
  GridMultigridHomogenization::write_vtu(
    const std::string                      &file_stem,
    const std::vector<std::string>         &cell_data_names,
    const std::vector<std::vector<double>> &cell_data) const
  {
    const Impl          &m    = *impl;
    const Level<double> &fine = m.fine;
    AssertThrow(m.solved, ExcMessage("write_vtu() needs a homogenize() first"));
    AssertThrow(cell_data.size() == cell_data_names.size(),
                ExcMessage("write_vtu(): one name per cell data field"));
    Triangulation<2> tria;
    GridGenerator::subdivided_hyper_rectangle(tria,
                                              {fine.nx, fine.ny},
                                              Point<2>(),
                                              Point<2>(fine.nx * fine.hx,
                                                       fine.ny * fine.hy));
    const FESystem<2> fe(FE_Q<2>(1), 2);
    DoFHandler<2>     dof_handler(tria);
    dof_handler.distribute_dofs(fe);

    // Vertex (i, j) of a cell holds grid node (i mod nx, j mod ny).
    std::array<Vector<double>, 3> w;
    for (auto &v : w)
      v.reinit(dof_handler.n_dofs());
    std::vector<std::vector<float>> data(
      cell_data.size(), std::vector<float>(tria.n_active_cells()));
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        const auto         center = cell->center();
        const unsigned int i      = std::min<unsigned int>(
          fine.nx - 1, static_cast<unsigned int>(center[0] / fine.hx));
        const unsigned int j = std::min<unsigned int>(
          fine.ny - 1, static_cast<unsigned int>(center[1] / fine.hy));
        const std::size_t pixel = i + fine.nx * std::size_t(j);
        for (unsigned int k = 0; k < data.size(); ++k)
          {
            AssertThrow(cell_data[k].size() == fine.voigt[0].size(),
                        ExcMessage("write_vtu(): cell data '" +
                                   cell_data_names[k] +
                                   "' needs one value per pixel"));
            data[k][cell->active_cell_index()] = cell_data[k][pixel];
          }
        cell->get_dof_indices(dofs);
        const auto node = cell_nodes(fine, i, j);
        for (unsigned int d = 0; d < fe.n_dofs_per_cell(); ++d)
          {
            // FE_Q vertex dofs in lexicographic vertex order, the local
            // node order of the grid
            const unsigned int v = fe.system_to_component_index(d).second,
                               c = fe.system_to_component_index(d).first;
            for (unsigned int a = 0; a < 3; ++a)
              w[a][dofs[d]] = m.solution[a * fine.block_size() +
                                         c * fine.n_nodes() + node[v]];
          }
      }

    DataOut<2> out;
    out.attach_dof_handler(dof_handler);
    const std::vector<DataComponentInterpretation::DataComponentInterpretation>
      vector(2, DataComponentInterpretation::component_is_part_of_vector);
    static const char *names[3] = {"w_11", "w_22", "w_12"};
    for (unsigned int a = 0; a < 3; ++a)
      out.add_data_vector(w[a],
                          std::vector<std::string>(2, names[a]),
                          DataOut<2>::type_dof_data,
                          vector);
    std::vector<Vector<float>> cell_vectors;
    for (const auto &d : data)
      cell_vectors.emplace_back(d.begin(), d.end());
    for (unsigned int k = 0; k < cell_vectors.size(); ++k)
      out.add_data_vector(cell_vectors[k],
                          cell_data_names[k],
                          DataOut<2>::type_cell_data);
    out.build_patches();
    std::ofstream file(file_stem + ".vtu");
    AssertThrow(file, ExcMessage("cannot write '" + file_stem + ".vtu'"));
    out.write_vtu(file);
  }
} // namespace forma
