#ifndef forma_ipc_obstacle_mesh_h
#define forma_ipc_obstacle_mesh_h

#include <forma/ipc/distance.h>

#include <array>
#include <string>
#include <vector>

namespace forma
{
  namespace ipc
  {
    /// A static obstacle surface: segments (2D) or triangles (3D).
    struct ObstacleMesh
    {
      std::vector<Vec>                         vertices;
      std::vector<std::array<unsigned int, 2>> edges; ///< 2D
      std::vector<std::array<unsigned int, 3>> faces; ///< 3D
    };

    /**
     * Read a static obstacle for IPC: a Gmsh mesh (`.msh`: its elements of
     * dimension dim - 1, or the boundary of its dim-dimensional elements if
     * it has none; higher-order elements by their corners), an STL file
     * (3D, through Gmsh) or a Wavefront OBJ file (`v` vertices, `f` faces
     * split into triangles in 3D, `l` polylines in 2D). 2D files must lie in
     * the plane z = 0. Throws with the file name if the file cannot be read
     * or holds no usable element.
     */
    ObstacleMesh
    read_obstacle_mesh(const std::string &file, const unsigned int dim);
  } // namespace ipc
} // namespace forma

#endif
