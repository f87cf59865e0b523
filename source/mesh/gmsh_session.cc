#include "gmsh_session.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <forma/base/application.h>

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



    std::string
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
      return gmsh_written_mesh();
    }



    std::string
    gmsh_on_root(const MPI_Comm                      comm,
                 const std::string                  &model,
                 const std::string                  &context,
                 const std::function<std::string()> &generate)
    {
      std::string msh, error;
      if (Utilities::MPI::this_mpi_process(comm) == 0)
        try
          {
            std::lock_guard<std::mutex> lock(gmsh_mutex());
            GmshSession                 session(model);
            msh = generate();
          }
        catch (const std::string &message) // what the Gmsh API throws
          {
            error = gmsh_error(context, "failed (" + message + ")");
          }
        catch (const std::exception &e)
          {
            error = error_message(e);
          }
        catch (...)
          {
            error = context + ": meshing failed with an unknown error";
          }
      std::tie(msh, error) =
        Utilities::MPI::broadcast(comm, std::make_pair(msh, error));
      AssertThrow(error.empty(), ExcMessage(error));
      return msh;
    }
  } // namespace internal
} // namespace forma
