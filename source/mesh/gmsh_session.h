#ifndef forma_source_mesh_gmsh_session_h
#define forma_source_mesh_gmsh_session_h

// Internal helpers for the library's Gmsh API users (not installed).

#include <deal.II/base/mpi.h>

#include <functional>
#include <mutex>
#include <string>

namespace forma
{
  namespace internal
  {
    /// Gmsh is a global singleton: hold this while a session is open.
    std::mutex &
    gmsh_mutex();

    /// One initialized Gmsh model, quiet and single-threaded, finalized on
    /// destruction.
    struct GmshSession
    {
      explicit GmshSession(const std::string &model);
      ~GmshSession();
    };

    /// "`context`: Gmsh `what`: <Gmsh's last error>".
    std::string
    gmsh_error(const std::string &context, const std::string &what);

    /// Throw if meshing logged an error or left an entity of dimension
    /// `dim` without elements.
    void
    gmsh_check_generated(const int dim, const std::string &context);

    /// The mesh Gmsh holds as a 2.2 ASCII file (what GridIn reads).
    std::string
    gmsh_written_mesh();

    /// Mesh the model's surfaces with triangles of at most `size`
    /// (Frontal-Delaunay, sizes extended from the boundary), check the
    /// result and return it as gmsh_written_mesh() does.
    std::string
    gmsh_triangulate(const double size, const std::string &context);

    /// Run `generate` (it builds a model and returns the mesh text) in a
    /// Gmsh session on the root of `comm` only, so that every rank reads
    /// the same mesh: every rank gets the text, or throws the root's error
    /// (collective).
    std::string
    gmsh_on_root(const MPI_Comm                      comm,
                 const std::string                  &model,
                 const std::string                  &context,
                 const std::function<std::string()> &generate);
  } // namespace internal
} // namespace forma

#endif
