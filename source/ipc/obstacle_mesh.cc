#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <forma/ipc/obstacle_mesh.h>

#include "../mesh/gmsh_session.h"
#include <gmsh.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace forma
{
  namespace ipc
  {
    using namespace dealii;

    namespace
    {
      /// The primitives of dimension dim - 1 of a list of elements given as
      /// corner lists: themselves, or for dim-dimensional elements their
      /// faces that belong to one element only (the boundary).
      void
      add_primitives(const std::vector<std::vector<unsigned int>> &elements,
                     const unsigned int                            dim,
                     const bool                                    volume,
                     ObstacleMesh                                 &m)
      {
        std::vector<std::vector<unsigned int>> prims;
        if (!volume)
          prims = elements;
        else
          {
            std::map<std::vector<unsigned int>,
                     std::pair<unsigned int, std::vector<unsigned int>>>
              count;
            for (const auto &e : elements)
              {
                std::vector<std::vector<unsigned int>> f;
                const unsigned int                     n = e.size();
                if (dim == 2 && (n == 3 || n == 4)) // their edges
                  for (unsigned int i = 0; i < n; ++i)
                    f.push_back({e[i], e[(i + 1) % n]});
                else if (n == 4) // tetrahedra
                  f = {{e[0], e[2], e[1]},
                       {e[0], e[1], e[3]},
                       {e[1], e[2], e[3]},
                       {e[0], e[3], e[2]}};
                else if (n == 8) // hexahedra (Gmsh order)
                  f = {{e[0], e[3], e[2], e[1]},
                       {e[4], e[5], e[6], e[7]},
                       {e[0], e[1], e[5], e[4]},
                       {e[1], e[2], e[6], e[5]},
                       {e[2], e[3], e[7], e[6]},
                       {e[3], e[0], e[4], e[7]}};
                AssertThrow(!f.empty(),
                            ExcMessage("IPC/Obstacles: a cell with " +
                                       std::to_string(n) +
                                       " corners: obstacle meshes take "
                                       "triangles and quadrilaterals in 2D, "
                                       "tetrahedra and hexahedra in 3D."));
                for (const auto &face : f)
                  {
                    auto key = face;
                    std::sort(key.begin(), key.end());
                    auto &c = count[key];
                    ++c.first;
                    c.second = face;
                  }
              }
            for (const auto &c : count)
              if (c.second.first == 1)
                prims.push_back(c.second.second);
          }
        for (const auto &p : prims)
          if (dim == 2)
            m.edges.push_back({{p[0], p[1]}});
          else
            for (unsigned int i = 1; i + 1 < p.size(); ++i)
              m.faces.push_back({{p[0], p[i], p[i + 1]}});
      }



      ObstacleMesh
      read_with_gmsh(const std::string &file, const unsigned int dim)
      {
        std::lock_guard<std::mutex> lock(internal::gmsh_mutex());
        internal::GmshSession       session("obstacle");
        ObstacleMesh                m;
        // Gmsh logs errors here (General.AbortOnError = 0) instead of
        // throwing: check its log.
        std::string last;
        try
          {
            gmsh::open(file);
            gmsh::logger::getLastError(last);
          }
        catch (...)
          {
            last = "?";
          }
        AssertThrow(last.empty(),
                    ExcMessage(internal::gmsh_error(
                      "IPC/Obstacles", "could not read '" + file + "'")));
        std::vector<std::size_t> tags;
        std::vector<double>      coords, parametric;
        gmsh::model::mesh::getNodes(tags, coords, parametric, -1, -1, true);
        std::map<std::size_t, unsigned int> index;
        for (unsigned int i = 0; i < tags.size(); ++i)
          {
            index[tags[i]] = m.vertices.size();
            m.vertices.push_back(
              Vec({coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]}));
          }
        for (const bool volume : {false, true})
          {
            std::vector<int>                      types;
            std::vector<std::vector<std::size_t>> etags, enodes;
            gmsh::model::mesh::getElements(
              types, etags, enodes, volume ? dim : dim - 1, -1);
            std::vector<std::vector<unsigned int>> elements;
            for (unsigned int k = 0; k < types.size(); ++k)
              {
                std::string         name;
                int                 edim, order, n_nodes, n_corners;
                std::vector<double> local;
                gmsh::model::mesh::getElementProperties(
                  types[k], name, edim, order, n_nodes, local, n_corners);
                for (unsigned int e = 0; e * n_nodes < enodes[k].size(); ++e)
                  {
                    std::vector<unsigned int> c;
                    for (int i = 0; i < n_corners; ++i)
                      c.push_back(index.at(enodes[k][e * n_nodes + i]));
                    elements.push_back(c);
                  }
              }
            if (!elements.empty())
              {
                add_primitives(elements, dim, volume, m);
                break;
              }
          }
        return m;
      }



      ObstacleMesh
      read_obj(const std::string &file, const unsigned int dim)
      {
        std::ifstream in(file);
        AssertThrow(in,
                    ExcMessage("IPC/Obstacles: cannot open '" + file + "'."));
        ObstacleMesh                           m;
        std::vector<std::vector<unsigned int>> elements;
        std::string                            line;
        unsigned int                           line_no = 0;
        while (std::getline(in, line))
          {
            ++line_no;
            std::istringstream s(line.substr(0, line.find('#')));
            std::string        key;
            s >> key;
            if (key == "v")
              {
                Vec x;
                s >> x[0] >> x[1] >> x[2];
                AssertThrow(!s.fail(),
                            ExcMessage("IPC/Obstacles: '" + file + "', line " +
                                       std::to_string(line_no) +
                                       ": a vertex needs three coordinates."));
                m.vertices.push_back(x);
              }
            else if ((key == "f" && dim == 3) || (key == "l" && dim == 2))
              {
                // "i", "i/t" or "i/t/n"; negative indices count from the end.
                std::vector<unsigned int> e;
                std::string               item;
                while (s >> item)
                  {
                    const int i =
                      Utilities::string_to_int(item.substr(0, item.find('/')));
                    const int k = i > 0 ? i - 1 : int(m.vertices.size()) + i;
                    AssertThrow(k >= 0 && k < int(m.vertices.size()),
                                ExcMessage(
                                  "IPC/Obstacles: '" + file + "', line " +
                                  std::to_string(line_no) + ": vertex index " +
                                  item + " out of range."));
                    e.push_back(k);
                  }
                if (dim == 2)
                  for (unsigned int i = 0; i + 1 < e.size(); ++i)
                    elements.push_back({e[i], e[i + 1]});
                else if (e.size() >= 3)
                  elements.push_back(e);
              }
          }
        add_primitives(elements, dim, false, m);
        return m;
      }
    } // namespace



    ObstacleMesh
    read_obstacle_mesh(const std::string &file, const unsigned int dim)
    {
      AssertThrow(std::filesystem::exists(file),
                  ExcMessage("IPC/Obstacles: the file '" + file +
                             "' does not exist."));
      std::string ext = std::filesystem::path(file).extension().string();
      for (auto &ch : ext)
        ch = std::tolower(ch);
      ObstacleMesh m;
      if (ext == ".obj")
        m = read_obj(file, dim);
      else
        {
          AssertThrow(ext == ".msh" || ext == ".stl",
                      ExcMessage("IPC/Obstacles: '" + file +
                                 "': obstacle meshes are .msh, .stl or .obj "
                                 "files."));
          AssertThrow(dim == 3 || ext == ".msh",
                      ExcMessage("IPC/Obstacles: '" + file +
                                 "': STL surfaces are 3D obstacles."));
          m = read_with_gmsh(file, dim);
        }
      AssertThrow(!(dim == 2 ? m.edges.empty() : m.faces.empty()),
                  ExcMessage("IPC/Obstacles: '" + file + "' holds no " +
                             (dim == 2 ? "segments" : "triangles") + " for a " +
                             std::to_string(dim) + "D obstacle."));
      // Drop vertices no primitive uses.
      std::vector<int> used(m.vertices.size(), -1);
      ObstacleMesh     r;
      const auto       map = [&](unsigned int v) {
        if (used[v] < 0)
          {
            used[v] = r.vertices.size();
            r.vertices.push_back(m.vertices[v]);
          }
        return unsigned(used[v]);
      };
      // Degenerate primitives (repeated or collinear corners) have no
      // contact geometry: drop them.
      double size = 0;
      for (const Vec &x : m.vertices)
        size = std::max(size, x.norm());
      for (const auto &e : m.edges)
        if ((m.vertices[e[1]] - m.vertices[e[0]]).norm() > 1e-12 * size)
          r.edges.push_back({{map(e[0]), map(e[1])}});
      for (const auto &f : m.faces)
        if (cross_product_3d(m.vertices[f[1]] - m.vertices[f[0]],
                             m.vertices[f[2]] - m.vertices[f[0]])
              .norm() > 1e-12 * size * size)
          r.faces.push_back({{map(f[0]), map(f[1]), map(f[2])}});
      if (dim == 2)
        for (const Vec &x : r.vertices)
          AssertThrow(x[2] == 0,
                      ExcMessage("IPC/Obstacles: '" + file +
                                 "': a 2D obstacle must lie in z = 0."));
      return r;
    }
  } // namespace ipc
} // namespace forma
