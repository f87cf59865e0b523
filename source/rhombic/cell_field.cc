#include <deal.II/grid/tria.h>

#include <forma/base/plot.h>
#include <forma/rhombic/study.h>

namespace forma
{
  namespace rhombic
  {
    void
    write_cell_field(const std::string                 &file_name,
                     const dealii::Triangulation<2, 2> &tria,
                     const std::vector<double>         &values,
                     const std::array<double, 2>       &range,
                     const std::string                 &label,
                     const unsigned int                 width)
    {
      std::vector<std::vector<std::array<double, 2>>> polygons;
      for (const auto &cell : tria.active_cell_iterators())
        {
          // Around the cell: deal.II numbers quad vertices lexicographically.
          const std::vector<unsigned int> order =
            cell->n_vertices() == 4 ? std::vector<unsigned int>{0, 1, 3, 2} :
                                      std::vector<unsigned int>{0, 1, 2};
          std::vector<std::array<double, 2>> p;
          for (const unsigned int v : order)
            p.push_back({{cell->vertex(v)[0], cell->vertex(v)[1]}});
          polygons.push_back(p);
        }
      write_polygon_field(file_name, polygons, values, range, label, width);
    }
  } // namespace rhombic
} // namespace forma
