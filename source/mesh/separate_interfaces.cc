#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>
#include <deal.II/grid/tria.h>

#include <forma/base/records.h>
#include <forma/mesh/separate_interfaces.h>

#include <algorithm>
#include <map>
#include <numeric>

namespace forma
{
  using namespace dealii;

  std::vector<InterfaceCut>
  parse_interface_cuts(const std::string &text, const std::string &entry)
  {
    std::vector<InterfaceCut> cuts;
    for (const auto &record : split_top_level(text, ';'))
      {
        if (Utilities::trim(record).empty())
          continue;
        const auto fields = split_top_level(record, ':');
        const auto pair   = fields.empty() ?
                              std::vector<std::string>() :
                              Utilities::split_string_list(fields[0], '-');
        AssertThrow(fields.size() == 2 && pair.size() == 2,
                    ExcMessage("'" + entry + "': the record '" + record +
                               "' must read 'material-material : boundary "
                               "id', e.g. '1-2 : 10'."));
        InterfaceCut c;
        try
          {
            c.first    = Utilities::string_to_int(pair[0]);
            c.second   = Utilities::string_to_int(pair[1]);
            c.boundary = Utilities::string_to_int(fields[1]);
          }
        catch (...)
          {
            AssertThrow(false,
                        ExcMessage("'" + entry + "': the record '" + record +
                                   "' has a non-integer id."));
          }
        AssertThrow(c.first != c.second,
                    ExcMessage("'" + entry + "': the record '" + record +
                               "' names the same material twice."));
        cuts.push_back(c);
      }
    return cuts;
  }



  template <int dim>
  void
  separate_interfaces(Triangulation<dim>              &tria,
                      const std::vector<InterfaceCut> &cuts,
                      const std::string               &where)
  {
    if (cuts.empty())
      return;
    AssertThrow(tria.n_levels() == 1,
                ExcMessage(where + ": interfaces are cut on the coarse mesh, "
                                   "before any refinement."));
    auto cut_of = [&](const types::material_id a, const types::material_id b) {
      for (unsigned int k = 0; k < cuts.size(); ++k)
        if ((cuts[k].first == a && cuts[k].second == b) ||
            (cuts[k].first == b && cuts[k].second == a))
          return static_cast<int>(k);
      return -1;
    };
    using Cell = typename Triangulation<dim>::active_cell_iterator;
    std::vector<Cell> cells(tria.n_active_cells());
    for (const auto &cell : tria.active_cell_iterators())
      cells[cell->active_cell_index()] = cell;

    // The cut faces, their vertices and the cells around every vertex.
    std::vector<Point<dim>>                vertices = tria.get_vertices();
    std::vector<std::vector<unsigned int>> vertex_cells(vertices.size());
    std::vector<bool>                      on_cut(vertices.size(), false);
    std::vector<unsigned int>              faces_of_cut(cuts.size(), 0);
    auto face_cut = [&](const Cell &cell, const unsigned int f) {
      if (cell->face(f)->at_boundary())
        return -1;
      return cut_of(cell->material_id(), cell->neighbor(f)->material_id());
    };
    for (const auto &cell : cells)
      {
        for (const auto v : cell->vertex_indices())
          vertex_cells[cell->vertex_index(v)].push_back(
            cell->active_cell_index());
        for (const auto f : cell->face_indices())
          if (const int k = face_cut(cell, f); k >= 0)
            {
              ++faces_of_cut[k];
              for (const auto i : cell->face(f)->vertex_indices())
                on_cut[cell->face(f)->vertex_index(i)] = true;
            }
      }
    for (unsigned int k = 0; k < cuts.size(); ++k)
      AssertThrow(faces_of_cut[k] > 0,
                  ExcMessage(where + ": materials " +
                             std::to_string(cuts[k].first) + " and " +
                             std::to_string(cuts[k].second) +
                             " share no face, so there is no interface to "
                             "separate (check the physical tags)."));

    // Per cell, its vertices in the new numbering. Around a vertex on a cut,
    // the cells joined through uncut faces that contain it form one group;
    // every group but the first gets its own copy of the vertex.
    std::vector<std::vector<unsigned int>> cell_vertices(cells.size());
    for (const auto &cell : cells)
      for (const auto v : cell->vertex_indices())
        cell_vertices[cell->active_cell_index()].push_back(
          cell->vertex_index(v));
    for (unsigned int v = 0; v < on_cut.size(); ++v)
      {
        if (!on_cut[v])
          continue;
        const auto               &around = vertex_cells[v];
        std::vector<unsigned int> root(around.size());
        std::iota(root.begin(), root.end(), 0u);
        auto find = [&](unsigned int i) {
          while (root[i] != i)
            i = root[i] = root[root[i]];
          return i;
        };
        for (unsigned int a = 0; a < around.size(); ++a)
          {
            const Cell &cell = cells[around[a]];
            for (const auto f : cell->face_indices())
              {
                if (cell->face(f)->at_boundary() || face_cut(cell, f) >= 0)
                  continue;
                bool contains = false;
                for (const auto i : cell->face(f)->vertex_indices())
                  contains |= cell->face(f)->vertex_index(i) == v;
                if (!contains)
                  continue;
                const auto n =
                  std::find(around.begin(),
                            around.end(),
                            cell->neighbor(f)->active_cell_index());
                if (n != around.end())
                  root[find(a)] = find(n - around.begin());
              }
          }
        std::map<unsigned int, unsigned int> copy_of_group;
        for (unsigned int a = 0; a < around.size(); ++a)
          {
            const unsigned int g = find(a);
            if (!copy_of_group.count(g))
              {
                copy_of_group[g] = copy_of_group.empty() ? v : vertices.size();
                if (copy_of_group[g] != v)
                  vertices.push_back(vertices[v]);
              }
            const Cell &cell = cells[around[a]];
            for (const auto l : cell->vertex_indices())
              if (cell->vertex_index(l) == v)
                cell_vertices[around[a]][l] = copy_of_group[g];
          }
      }

    // Rebuild: cells with their material ids, boundary faces (old ones and
    // both sides of every cut) with their boundary ids.
    std::vector<CellData<dim>> cell_data;
    SubCellData                sub;
    for (const auto &cell : cells)
      {
        const unsigned int c = cell->active_cell_index();
        CellData<dim>      d(cell->n_vertices());
        d.vertices    = cell_vertices[c];
        d.material_id = cell->material_id();
        cell_data.push_back(d);
        for (const auto f : cell->face_indices())
          {
            const int k = face_cut(cell, f);
            if (!cell->face(f)->at_boundary() && k < 0)
              continue;
            CellData<dim - 1> face(cell->face(f)->n_vertices());
            for (const auto i : cell->face(f)->vertex_indices())
              for (const auto l : cell->vertex_indices())
                if (cell->vertex_index(l) == cell->face(f)->vertex_index(i))
                  face.vertices[i] = cell_vertices[c][l];
            face.boundary_id =
              k >= 0 ? cuts[k].boundary : cell->face(f)->boundary_id();
            if constexpr (dim == 2)
              sub.boundary_lines.push_back(face);
            else
              sub.boundary_quads.push_back(face);
          }
      }
    tria.clear();
    tria.create_triangulation(vertices, cell_data, sub);
  }

  template void
  separate_interfaces<2>(Triangulation<2> &,
                         const std::vector<InterfaceCut> &,
                         const std::string &);
  template void
  separate_interfaces<3>(Triangulation<3> &,
                         const std::vector<InterfaceCut> &,
                         const std::string &);
} // namespace forma
