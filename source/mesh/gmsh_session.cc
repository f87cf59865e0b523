#include "gmsh_session.h"

#include <deal.II/base/exceptions.h>

#include <gmsh.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
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



    GmshSession::GmshSession(const std::string &model)
    {
      gmsh::initialize();
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
  } // namespace internal
} // namespace forma
