// The symmetric cells of the level-set mesher: the mesh of a cell's lower
// half joined with its copy rotated by pi, and the boundary loops of a mesh.

#include "level_set_mesh_symmetry.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/grid/tria.h>

#include <forma/base/records.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace forma
{
  using namespace dealii;

  namespace
  {
    /// Disjoint sets of indices 0..n-1 (union-find with path halving).
    class DisjointSets
    {
    public:
      explicit DisjointSets(const unsigned int n)
        : parent(n)
      {
        std::iota(parent.begin(), parent.end(), 0u);
      }

      unsigned int
      root(unsigned int v)
      {
        while (parent[v] != v)
          v = parent[v] = parent[parent[v]];
        return v;
      }

      void
      join(const unsigned int a, const unsigned int b)
      {
        parent[root(a)] = root(b);
      }

    private:
      std::vector<unsigned int> parent;
    };
  } // namespace



  namespace internal
  {
    /// Closed chains of boundary edges (contours and the parts of the box's
    /// sides in the material) of a mesh.
    unsigned int
    count_boundary_loops(const Triangulation<2> &tria)
    {
      DisjointSets      chains(tria.n_vertices());
      std::vector<bool> on_boundary(tria.n_vertices(), false);
      for (const auto &cell : tria.active_cell_iterators())
        for (const auto &face : cell->face_iterators())
          if (face->at_boundary())
            {
              const unsigned int a = face->vertex_index(0),
                                 b = face->vertex_index(1);
              on_boundary[a] = on_boundary[b] = true;
              chains.join(a, b);
            }
      unsigned int loops = 0;
      for (unsigned int v = 0; v < tria.n_vertices(); ++v)
        loops += on_boundary[v] && chains.root(v) == v;
      return loops;
    }



    /**
     * The cell mesh from the mesh of its lower half (y <= L_1 / 2) and the
     * half's copy rotated by pi about the center, joined along y = L_1 / 2,
     * whose nodes are mirror-symmetric about x = L_0 / 2. Material that
     * reaches no side of the cell floats: its cells are dropped and the
     * pieces counted.
     */
    void
    join_rotated_copy(const GmshTriangles      &half,
                      const Point<2>           &box,
                      std::vector<Point<2>>    &vertices,
                      std::vector<CellData<2>> &cells,
                      unsigned int             &floating_pieces)
    {
      const double             tol = 1e-9 * std::max(box[0], box[1]);
      const double             mid = box[1] / 2;
      std::vector<int>         index(half.vertices.size(), -1);
      std::vector<Point<2>>    points;
      std::vector<CellData<2>> lower;
      for (const CellData<2> &cell : half.cells)
        {
          CellData<2> data(cell.vertices.size());
          for (unsigned int v = 0; v < cell.vertices.size(); ++v)
            {
              int &k = index[cell.vertices[v]];
              if (k < 0)
                {
                  k = points.size();
                  points.push_back(half.vertices[cell.vertices[v]]);
                }
              data.vertices[v] = k;
            }
          lower.push_back(data);
        }
      // The nodes on a line y = y0 are symmetric about x = L_0 / 2 (the
      // tracer mirrors them) up to round-off: snap them onto the line and
      // onto exact mirror images; returns each one's mirror node.
      const auto snap_mirrored = [&](const double y0) {
        std::vector<std::pair<double, unsigned int>> line;
        for (unsigned int k = 0; k < points.size(); ++k)
          if (std::abs(points[k][1] - y0) < tol)
            line.emplace_back(points[k][0], k);
        std::sort(line.begin(), line.end());
        std::map<unsigned int, unsigned int> mirror;
        for (const auto &[x, k] : line)
          {
            const auto it =
              std::lower_bound(line.begin(),
                               line.end(),
                               std::make_pair(box[0] - x - tol, 0u));
            AssertThrow(it != line.end() &&
                          std::abs(it->first - (box[0] - x)) < tol,
                        ExcMessage("symmetric cell mesh: the nodes on the "
                                   "line y = " +
                                   sig(y0, 4) +
                                   " are not symmetric (internal error)"));
            mirror[k] = it->second;
          }
        for (const auto &[k, m] : mirror)
          {
            points[k][1] = y0;
            if (points[k][0] > box[0] / 2) // its mirror node is left as is
              points[k][0] = box[0] - points[m][0];
          }
        return mirror;
      };
      // The bottom side's rotated copy is the top side: periodic partners.
      snap_mirrored(0);
      // On the joint each node's image is its mirror node.
      const std::map<unsigned int, unsigned int> joint = snap_mirrored(mid);
      std::vector<unsigned int>                  image(points.size());
      vertices = points;
      for (unsigned int k = 0; k < points.size(); ++k)
        if (const auto it = joint.find(k); it != joint.end())
          image[k] = it->second;
        else
          {
            image[k] = vertices.size();
            vertices.emplace_back(box[0] - points[k][0], box[1] - points[k][1]);
          }
      cells = lower;
      for (CellData<2> data : lower)
        {
          // A rotation keeps the orientation, so the vertex order too.
          for (unsigned int &v : data.vertices)
            v = image[v];
          cells.push_back(data);
        }

      // Pieces by shared vertices (union-find); keep those on a side.
      DisjointSets pieces(vertices.size());
      for (const CellData<2> &c : cells)
        for (const unsigned int v : c.vertices)
          pieces.join(v, c.vertices[0]);
      std::vector<bool> on_side(vertices.size(), false);
      for (unsigned int v = 0; v < vertices.size(); ++v)
        {
          const Point<2> &x = vertices[v];
          if (x[0] < tol || x[0] > box[0] - tol || x[1] < tol ||
              x[1] > box[1] - tol)
            on_side[pieces.root(v)] = true;
        }
      std::vector<bool>        counted(vertices.size(), false);
      std::vector<CellData<2>> kept;
      for (const CellData<2> &c : cells)
        {
          const unsigned int r = pieces.root(c.vertices[0]);
          if (on_side[r])
            kept.push_back(c);
          else if (!counted[r])
            {
              counted[r] = true;
              ++floating_pieces;
            }
        }
      if (kept.size() < cells.size())
        {
          // Renumber the vertices still used.
          std::vector<int>      renumber(vertices.size(), -1);
          std::vector<Point<2>> used;
          for (CellData<2> &c : kept)
            for (unsigned int &v : c.vertices)
              {
                if (renumber[v] < 0)
                  {
                    renumber[v] = used.size();
                    used.push_back(vertices[v]);
                  }
                v = renumber[v];
              }
          vertices = std::move(used);
        }
      cells = std::move(kept);
    }
  } // namespace internal
} // namespace forma
