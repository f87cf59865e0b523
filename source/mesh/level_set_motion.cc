#include <deal.II/base/exceptions.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/grid/tria.h>

#include <forma/mesh/harmonic_extension.h>
#include <forma/mesh/level_set_motion.h>

#include <array>
#include <cmath>
#include <map>

namespace forma
{
  using namespace dealii;

  struct LevelSetMeshMotion::Impl
  {
    enum Kind
    {
      interior,
      fixed,  ///< on a side, or a contour vertex that cannot move
      contour ///< moves along `direction`
    };

    std::vector<Point<2>>     vertices;
    std::vector<Kind>         kind;
    std::vector<Tensor<1, 2>> direction;
    std::vector<double>       slope; ///< grad phi . direction
    /// A vertex on an upper side: its partner on the lower side.
    std::vector<int> partner;
    Point<2>         box;

    // The interior follows the boundary by the library's harmonic
    // extension, on a vector P1 field over a copy of the mesh.
    Triangulation<2>                         tria;
    const FESystem<2>                        fe{FE_SimplexP<2>(1), 2};
    const MappingFE<2>                       mapping{FE_SimplexP<2>(1)};
    DoFHandler<2>                            dof_handler;
    AffineConstraints<double>                no_constraints;
    std::vector<std::array<unsigned int, 2>> vertex_to_dof;
    std::unique_ptr<HarmonicExtension<2>>    extension;

    /// The interior displacements for given boundary displacements.
    std::vector<Tensor<1, 2>>
    extend(const std::vector<Tensor<1, 2>> &boundary) const
    {
      const IndexSet               owned = dof_handler.locally_owned_dofs();
      HarmonicExtension<2>::Vector x(owned, MPI_COMM_SELF);
      for (unsigned int v = 0; v < vertices.size(); ++v)
        for (unsigned int d = 0; d < 2; ++d)
          if (vertex_to_dof[v][d] != numbers::invalid_unsigned_int)
            x(vertex_to_dof[v][d]) = boundary[v][d];
      x.compress(VectorOperation::insert);
      extension->extend(x);
      std::vector<Tensor<1, 2>> result(vertices.size());
      for (unsigned int v = 0; v < vertices.size(); ++v)
        for (unsigned int d = 0; d < 2; ++d)
          if (vertex_to_dof[v][d] != numbers::invalid_unsigned_int)
            result[v][d] = x(vertex_to_dof[v][d]);
      return result;
    }
  };



  LevelSetMeshMotion::LevelSetMeshMotion(
    const Triangulation<2>                        &mesh,
    const Point<2>                                &box,
    const std::function<double(const Point<2> &)> &phi)
    : impl(std::make_unique<Impl>())
  {
    Impl &m = *impl;
    m.box   = box;
    m.tria.copy_triangulation(mesh);
    m.vertices            = m.tria.get_vertices();
    const unsigned int nv = m.vertices.size();
    m.kind.assign(nv, Impl::interior);
    m.direction.assign(nv, Tensor<1, 2>());
    m.slope.assign(nv, 0.);
    m.partner.assign(nv, -1);

    const double scale   = std::max(box[0], box[1]);
    const auto   on_side = [&](const Point<2> &x, const unsigned int d) {
      return std::abs(x[d]) < 1e-8 * scale ||
             std::abs(x[d] - box[d]) < 1e-8 * scale;
    };
    std::vector<bool> on_contour(nv, false), on_boundary(nv, false);
    for (const auto &cell : m.tria.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          {
            const Point<2> c    = cell->face(f)->center();
            const bool     side = on_side(c, 0) || on_side(c, 1);
            for (unsigned int v = 0; v < 2; ++v)
              {
                const unsigned int i = cell->face(f)->vertex_index(v);
                on_boundary[i]       = true;
                if (!side)
                  on_contour[i] = true;
              }
          }

    const double h        = 1e-7 * scale;
    const auto   gradient = [&](const Point<2> &x) {
      Tensor<1, 2> g;
      for (unsigned int d = 0; d < 2; ++d)
        {
          Point<2> a = x, b = x;
          a[d] -= h, b[d] += h;
          g[d] = (phi(b) - phi(a)) / (2 * h);
        }
      return g;
    };
    for (unsigned int i = 0; i < nv; ++i)
      {
        if (!on_boundary[i])
          continue;
        m.kind[i]          = Impl::fixed;
        const Point<2> &x  = m.vertices[i];
        const bool      s0 = on_side(x, 0), s1 = on_side(x, 1);
        if (!on_contour[i] || (s0 && s1))
          continue;
        const Tensor<1, 2> g = gradient(x);
        if (!s0 && !s1)
          {
            if (g.norm() > 1e-8)
              {
                m.kind[i]      = Impl::contour;
                m.direction[i] = g / g.norm();
                m.slope[i]     = g.norm();
              }
          }
        else
          {
            // Slide along the side; a contour tangent to the side stays.
            const unsigned int along = s0 ? 1 : 0;
            if (std::abs(g[along]) > 1e-3 * g.norm())
              {
                m.kind[i]             = Impl::contour;
                m.direction[i][along] = 1;
                m.slope[i]            = g[along];
              }
          }
      }
    // Upper-side vertices copy their lower partner's motion exactly.
    std::map<std::array<long long, 2>, unsigned int> lower;
    const auto key = [&](const Point<2> &x) {
      return std::array<long long, 2>{
        {std::llround(x[0] / scale * 1e9), std::llround(x[1] / scale * 1e9)}};
    };
    for (unsigned int i = 0; i < nv; ++i)
      if (m.kind[i] == Impl::contour &&
          (std::abs(m.vertices[i][0]) < 1e-8 * scale ||
           std::abs(m.vertices[i][1]) < 1e-8 * scale))
        lower[key(m.vertices[i])] = i;
    for (unsigned int i = 0; i < nv; ++i)
      if (m.kind[i] == Impl::contour)
        for (unsigned int d = 0; d < 2; ++d)
          if (std::abs(m.vertices[i][d] - box[d]) < 1e-8 * scale)
            {
              Point<2> image = m.vertices[i];
              image[d]       = 0;
              const auto it  = lower.find(key(image));
              if (it != lower.end())
                m.partner[i] = it->second;
              else
                m.kind[i] = Impl::fixed; // no partner: keep it in place
            }

    // Vertex DoFs of the vector P1 field the extension acts on.
    m.dof_handler.reinit(m.tria);
    m.dof_handler.distribute_dofs(m.fe);
    m.no_constraints.close();
    const unsigned int invalid = numbers::invalid_unsigned_int;
    m.vertex_to_dof.assign(nv, {{invalid, invalid}});
    for (const auto &cell : m.dof_handler.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        for (unsigned int d = 0; d < 2; ++d)
          m.vertex_to_dof[cell->vertex_index(v)][d] =
            cell->vertex_dof_index(v, d);
    m.extension = std::make_unique<HarmonicExtension<2>>(m.dof_handler,
                                                         m.no_constraints,
                                                         m.mapping,
                                                         MPI_COMM_SELF);
  }



  LevelSetMeshMotion::~LevelSetMeshMotion() = default;



  std::vector<std::vector<Tensor<1, 2>>>
  LevelSetMeshMotion::velocities(
    const std::function<std::vector<double>(const Point<2> &)> &dphi_dq,
    const unsigned int n_variables) const
  {
    const Impl                            &m = *impl;
    std::vector<std::vector<Tensor<1, 2>>> boundary(
      n_variables, std::vector<Tensor<1, 2>>(m.vertices.size()));
    for (unsigned int i = 0; i < m.vertices.size(); ++i)
      if (m.kind[i] == Impl::contour && m.partner[i] < 0)
        {
          const std::vector<double> dq = dphi_dq(m.vertices[i]);
          AssertThrow(dq.size() == n_variables,
                      ExcMessage(
                        "LevelSetMeshMotion: " + std::to_string(dq.size()) +
                        " level-set derivatives for " +
                        std::to_string(n_variables) + " variables"));
          for (unsigned int k = 0; k < dq.size(); ++k)
            boundary[k][i] = -dq[k] / m.slope[i] * m.direction[i];
        }
    for (unsigned int i = 0; i < m.vertices.size(); ++i)
      if (m.partner[i] >= 0)
        for (auto &b : boundary)
          b[i] = b[m.partner[i]];
    std::vector<std::vector<Tensor<1, 2>>> result;
    for (const auto &b : boundary)
      result.push_back(m.extend(b));
    return result;
  }



  std::vector<Point<2>>
  LevelSetMeshMotion::moved_vertices(
    const std::function<double(const Point<2> &)> &new_phi) const
  {
    const Impl               &m = *impl;
    std::vector<Tensor<1, 2>> boundary(m.vertices.size());
    for (unsigned int i = 0; i < m.vertices.size(); ++i)
      if (m.kind[i] == Impl::contour && m.partner[i] < 0)
        {
          // Newton on t -> new_phi(x + t direction), slope from the start.
          double t = 0;
          for (unsigned int it = 0; it < 20; ++it)
            {
              const double f  = new_phi(m.vertices[i] + t * m.direction[i]);
              const double dt = -f / m.slope[i];
              t += dt;
              if (std::abs(dt) < 1e-14 * std::max(m.box[0], m.box[1]))
                break;
            }
          boundary[i] = t * m.direction[i];
        }
    for (unsigned int i = 0; i < m.vertices.size(); ++i)
      if (m.partner[i] >= 0)
        boundary[i] = boundary[m.partner[i]];
    const auto            displacement = m.extend(boundary);
    std::vector<Point<2>> result(m.vertices);
    for (unsigned int i = 0; i < result.size(); ++i)
      result[i] += displacement[i];
    return result;
  }



  void
  LevelSetMeshMotion::set_vertices(Triangulation<2>            &tria,
                                   const std::vector<Point<2>> &vertices)
  {
    AssertThrow(vertices.size() == tria.n_vertices(),
                ExcMessage("set_vertices: " + std::to_string(vertices.size()) +
                           " positions for " +
                           std::to_string(tria.n_vertices()) + " vertices"));
    std::vector<bool> done(vertices.size(), false);
    for (const auto &cell : tria.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        if (!done[cell->vertex_index(v)])
          {
            cell->vertex(v)             = vertices[cell->vertex_index(v)];
            done[cell->vertex_index(v)] = true;
          }
  }



  unsigned int
  LevelSetMeshMotion::n_moving_vertices() const
  {
    unsigned int n = 0;
    for (const auto k : impl->kind)
      n += (k == Impl::contour);
    return n;
  }
} // namespace forma
