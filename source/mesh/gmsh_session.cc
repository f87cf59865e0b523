#include "gmsh_session.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/grid/grid_tools.h>

#include <forma/base/application.h>
#include <forma/base/on_root.h>

#include <gmsh.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>
#include <utility>
#include <vector>

namespace forma
{
  namespace internal
  {
    using namespace dealii;

    std::mutex &
    gmsh_mutex()
    {
      static std::mutex m;
      return m;
    }



    namespace
    {
      // Gmsh 4.8's initialize() appends its own directory to PATH and
      // PYTHONPATH, every time. glibc never frees a replaced variable, so
      // with one session per cell mesh the environment grew by a copy of an
      // ever longer PATH per mesh: quadratic memory, 12 GB after an hour of
      // build map. Restoring the variables makes Gmsh's next setenv() an
      // identical string, which glibc reuses. (setenv is not thread-safe:
      // sessions are serialized by gmsh_mutex(), and nothing else reads the
      // environment meanwhile.)
      class EnvironmentGuard
      {
      public:
        EnvironmentGuard()
        {
          for (const char *name : names)
            {
              const char *value = std::getenv(name);
              saved.emplace_back(value != nullptr, value ? value : "");
            }
        }

        ~EnvironmentGuard()
        {
          for (unsigned int i = 0; i < names.size(); ++i)
            if (saved[i].first)
              ::setenv(names[i], saved[i].second.c_str(), 1);
            else
              ::unsetenv(names[i]);
        }

      private:
        static constexpr std::array<const char *, 2> names{
          {"PATH", "PYTHONPATH"}};
        std::vector<std::pair<bool, std::string>> saved;
      };
    } // namespace



    GmshSession::GmshSession(const std::string &model)
    {
      {
        const EnvironmentGuard guard;
        gmsh::initialize();
      }
      gmsh::option::setNumber("General.Terminal", 0);
      // Errors must not be thrown from inside Gmsh's OpenMP regions (that
      // terminates the program): they are logged, and the result is
      // checked instead.
      gmsh::option::setNumber("General.AbortOnError", 0);
      gmsh::option::setNumber("General.NumThreads", 1);
      gmsh::model::add(model);
    }



    GmshSession::~GmshSession()
    {
      gmsh::finalize();
    }



    std::string
    gmsh_error(const std::string &context, const std::string &what)
    {
      std::string last;
      try
        {
          gmsh::logger::getLastError(last);
        }
      catch (...)
        {}
      return context + ": Gmsh " + what + (last.empty() ? "" : ": " + last);
    }



    void
    gmsh_check_generated(const int dim, const std::string &context)
    {
      std::string last;
      gmsh::logger::getLastError(last);
      AssertThrow(last.empty(), ExcMessage(context + ": Gmsh failed: " + last));
      gmsh::vectorpair entities;
      gmsh::model::getEntities(entities, dim);
      for (const auto &e : entities)
        {
          std::vector<int>                      types;
          std::vector<std::vector<std::size_t>> tags, nodes;
          gmsh::model::mesh::getElements(types, tags, nodes, dim, e.second);
          AssertThrow(!types.empty(),
                      ExcMessage(context +
                                 ": Gmsh made no elements in a region (a "
                                 "self-intersecting boundary?)."));
        }
    }



    std::string
    gmsh_written_mesh()
    {
      gmsh::option::setNumber("Mesh.MshFileVersion", 2.2);
      gmsh::option::setNumber("Mesh.SaveAll", 0);
      const auto file = std::filesystem::temp_directory_path() /
                        ("forma-gmsh-" + std::to_string(::getpid()) + ".msh");
      gmsh::write(file.string());
      std::ifstream      in(file);
      std::ostringstream text;
      text << in.rdbuf();
      in.close();
      std::filesystem::remove(file);
      return text.str();
    }



    GmshTriangles
    gmsh_triangles()
    {
      GmshTriangles            result;
      std::vector<std::size_t> node_tags;
      std::vector<double>      coordinates, parametric;
      gmsh::model::mesh::getNodes(
        node_tags, coordinates, parametric, -1, -1, false, false);
      std::size_t largest = 0;
      for (const std::size_t t : node_tags)
        largest = std::max(largest, t);
      // Node tag -> vertex number, for the nodes the triangles use.
      std::vector<bool>         used(largest + 1, false);
      std::vector<unsigned int> vertex(largest + 1,
                                       numbers::invalid_unsigned_int);
      constexpr int             triangle = 2; // Gmsh's 3-node triangle
      gmsh::vectorpair          surfaces;
      gmsh::model::getEntities(surfaces, 2);
      std::vector<std::pair<int, std::vector<std::size_t>>> elements;
      for (const auto &surface : surfaces)
        {
          std::vector<int> groups;
          gmsh::model::getPhysicalGroupsForEntity(2, surface.second, groups);
          if (groups.empty())
            continue;
          // A .msh file would list the triangles once per group.
          AssertThrow(groups.size() == 1,
                      ExcMessage("Gmsh mesh: a surface in several physical "
                                 "groups"));
          std::vector<int>                      types;
          std::vector<std::vector<std::size_t>> tags, nodes;
          gmsh::model::mesh::getElements(types, tags, nodes, 2, surface.second);
          for (unsigned int k = 0; k < types.size(); ++k)
            {
              AssertThrow(types[k] == triangle,
                          ExcMessage("Gmsh made elements other than 3-node "
                                     "triangles (type " +
                                     std::to_string(types[k]) + ")"));
              for (const std::size_t t : nodes[k])
                used[t] = true;
              elements.emplace_back(groups[0], std::move(nodes[k]));
            }
        }
      // Numbered in tag order: Gmsh numbers a generated mesh's nodes entity
      // by entity, the order a .msh file lists them in.
      std::vector<std::size_t> order(node_tags.size());
      std::iota(order.begin(), order.end(), 0);
      std::sort(order.begin(), order.end(), [&](const auto a, const auto b) {
        return node_tags[a] < node_tags[b];
      });
      for (const std::size_t i : order)
        if (used[node_tags[i]])
          {
            vertex[node_tags[i]] = result.vertices.size();
            result.vertices.emplace_back(coordinates[3 * i],
                                         coordinates[3 * i + 1]);
          }
      for (const auto &[group, nodes] : elements)
        for (std::size_t e = 0; e + 2 < nodes.size(); e += 3)
          {
            CellData<2> cell(3);
            for (unsigned int v = 0; v < 3; ++v)
              cell.vertices[v] = vertex[nodes[e + v]];
            cell.material_id = group;
            result.cells.push_back(cell);
          }
      AssertThrow(!result.cells.empty(),
                  ExcMessage("Gmsh mesh: no triangles in a physical group"));
      // Clockwise triangles (a surface whose normal is -z) turned, as
      // GridIn does.
      GridTools::invert_cells_with_negative_measure(result.vertices,
                                                    result.cells);
      return result;
    }



    GmshTriangles
    gmsh_triangulate(const double size, const std::string &context)
    {
      gmsh::option::setNumber("Mesh.MeshSizeMax", size);
      gmsh::option::setNumber("Mesh.MeshSizeMin", 0);
      gmsh::option::setNumber("Mesh.MeshSizeFromPoints", 0);
      gmsh::option::setNumber("Mesh.MeshSizeFromCurvature", 0);
      gmsh::option::setNumber("Mesh.MeshSizeExtendFromBoundary", 1);
      gmsh::option::setNumber("Mesh.Algorithm", 6); // Frontal-Delaunay
      gmsh::model::mesh::generate(2);
      gmsh_check_generated(2, context);
      return gmsh_triangles();
    }



    void
    in_gmsh_session(const std::string           &model,
                    const std::string           &context,
                    const std::function<void()> &f)
    {
      try
        {
          std::lock_guard<std::mutex> lock(gmsh_mutex());
          GmshSession                 session(model);
          f();
        }
      catch (const std::string &message) // what the Gmsh API throws
        {
          AssertThrow(
            false, ExcMessage(gmsh_error(context, "failed (" + message + ")")));
        }
      catch (const std::exception &)
        {
          throw;
        }
      catch (...)
        {
          AssertThrow(false,
                      ExcMessage(context +
                                 ": meshing failed with an unknown error"));
        }
    }



    GmshTriangles
    gmsh_on_root(const MPI_Comm                        comm,
                 const std::string                    &model,
                 const std::string                    &context,
                 const std::function<GmshTriangles()> &generate)
    {
      return on_root_or_throw(comm, [&]() {
        GmshTriangles msh;
        in_gmsh_session(model, context, [&]() { msh = generate(); });
        return msh;
      });
    }
  } // namespace internal
} // namespace forma
