#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/dofs/dof_handler.h>

#include <forma/adjoint/shape_filter.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

namespace forma
{
  using namespace dealii;

  namespace
  {
    // A vertex of the shape field: its DoFs per component and which of
    // them are fixed, position on the mesh as read, and the materials of
    // the cells around it.
    template <int dim>
    struct Vertex
    {
      std::array<types::global_dof_index, dim> dofs;
      std::array<bool, dim>                    fixed;
      Point<dim>                               x;
      std::set<types::material_id>             materials;
    };

    // Packed as doubles for all_gather: dofs, fixed, x, n, materials.
    template <int dim>
    void
    pack(const Vertex<dim> &v, std::vector<double> &out)
    {
      for (const auto i : v.dofs)
        out.push_back(i);
      for (const bool f : v.fixed)
        out.push_back(f);
      for (unsigned int d = 0; d < dim; ++d)
        out.push_back(v.x[d]);
      out.push_back(v.materials.size());
      out.insert(out.end(), v.materials.begin(), v.materials.end());
    }

    template <int dim>
    std::vector<Vertex<dim>>
    unpack(const std::vector<std::vector<double>> &all)
    {
      std::vector<Vertex<dim>> result;
      for (const auto &data : all)
        for (unsigned int k = 0; k < data.size();)
          {
            Vertex<dim> v;
            for (unsigned int d = 0; d < dim; ++d)
              v.dofs[d] = static_cast<types::global_dof_index>(data[k++]);
            for (unsigned int d = 0; d < dim; ++d)
              v.fixed[d] = data[k++] != 0;
            for (unsigned int d = 0; d < dim; ++d)
              v.x[d] = data[k++];
            const unsigned int n = static_cast<unsigned int>(data[k++]);
            for (unsigned int m = 0; m < n; ++m)
              v.materials.insert(static_cast<types::material_id>(data[k++]));
            result.push_back(std::move(v));
          }
      return result;
    }

    // The filtered vertices of this rank (their first DoF locally owned).
    template <int dim>
    std::vector<Vertex<dim>>
    local_vertices(const DoFHandler<dim, dim> &dof_handler,
                   const std::function<bool(types::global_dof_index)> &filtered,
                   const std::function<bool(types::global_dof_index)> &fixed)
    {
      const IndexSet &owned = dof_handler.locally_owned_dofs();
      std::map<types::global_dof_index, Vertex<dim>> vertices;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (!cell->is_artificial())
          for (const auto v : cell->vertex_indices())
            {
              const auto i = cell->vertex_dof_index(v, 0);
              if (!owned.is_element(i) || !filtered(i))
                continue;
              auto &vertex = vertices[i];
              for (unsigned int d = 0; d < dim; ++d)
                {
                  vertex.dofs[d]  = cell->vertex_dof_index(v, d);
                  vertex.fixed[d] = fixed(vertex.dofs[d]);
                }
              vertex.x = cell->vertex(v);
              vertex.materials.insert(cell->material_id());
            }
      std::vector<Vertex<dim>> result;
      for (auto &[i, v] : vertices)
        result.push_back(std::move(v));
      return result;
    }

    template <int dim>
    bool
    share_a_material(const Vertex<dim> &a, const Vertex<dim> &b)
    {
      for (const auto m : a.materials)
        if (b.materials.count(m))
          return true;
      return false;
    }
  } // namespace



  template <int dim>
  ShapeFilter<dim>::ShapeFilter(
    const DoFHandler<dim, dim>                         &dof_handler,
    const double                                        radius,
    const std::function<bool(types::global_dof_index)> &filtered,
    const std::function<bool(types::global_dof_index)> &fixed,
    const MPI_Comm                                      comm)
    : rows(dof_handler.n_dofs())
  {
    AssertThrow(radius > 0,
                ExcMessage("Design/Shape filter radius must be > 0."));
    const auto          mine = local_vertices(dof_handler, filtered, fixed);
    std::vector<double> packed;
    for (const auto &v : mine)
      pack(v, packed);
    const auto all = unpack<dim>(Utilities::MPI::all_gather(comm, packed));

    // Buckets of side `radius`: the neighbours are in the 3^dim around.
    using Bucket         = std::array<long, dim>;
    const auto bucket_of = [&](const Point<dim> &x) {
      Bucket b;
      for (unsigned int d = 0; d < dim; ++d)
        b[d] = static_cast<long>(std::floor(x[d] / radius));
      return b;
    };
    std::map<Bucket, std::vector<unsigned int>> buckets;
    for (unsigned int k = 0; k < all.size(); ++k)
      buckets[bucket_of(all[k].x)].push_back(k);

    for (const auto &a : mine)
      {
        std::vector<std::pair<unsigned int, double>> near;
        double                                       total = 0;
        const Bucket                                 home  = bucket_of(a.x);
        for (unsigned int n = 0; n < std::pow(3, dim); ++n)
          {
            Bucket       b = home;
            unsigned int m = n;
            for (unsigned int d = 0; d < dim; ++d, m /= 3)
              b[d] += static_cast<long>(m % 3) - 1;
            const auto it = buckets.find(b);
            if (it != buckets.end())
              for (const auto k : it->second)
                if (const double w = 1 - a.x.distance(all[k].x) / radius;
                    w > 0 && share_a_material(a, all[k]))
                  near.emplace_back(k, w), total += w;
          }
        // A fixed neighbour counts as a zero entry: the moves fade out
        // towards fixed boundaries instead of shearing the cells there.
        for (unsigned int d = 0; d < dim; ++d)
          for (const auto &[k, w] : near)
            if (!all[k].fixed[d])
              rows[a.dofs[d]].emplace_back(all[k].dofs[d], w / total);
      }
  }



  template <int dim>
  double
  ShapeFilter<dim>::value(const double                 *q,
                          const types::global_dof_index i) const
  {
    if (rows[i].empty())
      return q[i];
    double sum = 0;
    for (const auto &[j, w] : rows[i])
      sum += w * q[j];
    return sum;
  }



  template <int dim>
  void
  ShapeFilter<dim>::add_transpose(const types::global_dof_index i,
                                  const double                  g,
                                  double                       *dJ) const
  {
    if (rows[i].empty())
      dJ[i] += g;
    else
      for (const auto &[j, w] : rows[i])
        dJ[j] += w * g;
  }



  template class ShapeFilter<2>;
  template class ShapeFilter<3>;
} // namespace forma
