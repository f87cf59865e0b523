#ifndef forma_source_mesh_gmsh_session_h
#define forma_source_mesh_gmsh_session_h

// Internal helpers for the library's Gmsh API users (not installed).

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/grid/tria_description.h>

#include <functional>
#include <mutex>
#include <string>
#include <vector>

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

    /// A planar triangle mesh as Triangulation::create_triangulation()
    /// takes it.
    struct GmshTriangles
    {
      std::vector<dealii::Point<2>>    vertices;
      std::vector<dealii::CellData<2>> cells;

      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int)
      {
        archive &vertices &cells;
      }
    };

    /// The triangles of the model's surfaces that belong to a physical
    /// group (one each), read from memory: what GridIn would make of
    /// gmsh_written_mesh()'s text, without the text. The nodes they use,
    /// numbered from 0 in Gmsh's order; the cells in Gmsh's order, clockwise
    /// ones turned, each with its surface's physical group tag as material
    /// id.
    GmshTriangles
    gmsh_triangles();

    /// Mesh the model's surfaces with triangles of at most `size`
    /// (Frontal-Delaunay, sizes extended from the boundary), check the
    /// result and return it as gmsh_triangles() does.
    GmshTriangles
    gmsh_triangulate(const double size, const std::string &context);

    /// Run f in a Gmsh session `model` (holding gmsh_mutex()); what Gmsh
    /// throws becomes an ExcMessage that names `context`.
    void
    in_gmsh_session(const std::string           &model,
                    const std::string           &context,
                    const std::function<void()> &f);

    /// Run `generate` (it builds a model and returns its mesh) in a Gmsh
    /// session on the root of `comm` only, so that every rank reads the
    /// same mesh: every rank gets the mesh, or throws the root's error
    /// (collective).
    GmshTriangles
    gmsh_on_root(const MPI_Comm                        comm,
                 const std::string                    &model,
                 const std::string                    &context,
                 const std::function<GmshTriangles()> &generate);
  } // namespace internal
} // namespace forma

#endif
