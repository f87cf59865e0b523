#include <deal.II/base/exceptions.h>
#include <deal.II/base/timer.h>
#include <deal.II/grid/tria.h>

#include <forma/base/outline.h>
#include <forma/homogenization/parallelogram_cell.h>
#include <forma/mesh/level_set_motion.h>
#include <forma/mesh/mesh.h>
#include <forma/mesh/polygon_domain.h>
#include <forma/rhombic/cell_model.h>

#include <Sacado.hpp>

#include <algorithm>
#include <filesystem>

namespace forma
{
  namespace rhombic
  {
    using namespace dealii;

    namespace
    {
      constexpr double L = RhombicStructure::side;
    }

    CellModel::CellModel(const RhombicStructure &structure,
                         const Setup            &setup,
                         const MPI_Comm          comm)
      : start(structure)
      , design(structure)
      , setup(setup)
      , comm(comm)
      , mesh(std::make_unique<Triangulation<2>>())
    {
      Timer                  timer;
      LevelSetMeshParameters mesh_parameters = setup.mesh;
      mesh_parameters.centrally_symmetric    = setup.symmetric_mesh;
      periodic_level_set_mesh(structure.level_set(),
                              Point<2>(L, L),
                              mesh_parameters,
                              *mesh,
                              comm,
                              &current.mesh,
                              "rhombic cell");
      const double seconds_mesh = timer.wall_time();
      homogenize();
      current.seconds_mesh = seconds_mesh;
    }



    CellModel::~CellModel() = default;



    Sample
    evaluate(const RhombicStructure &structure,
             const Setup            &setup,
             const MPI_Comm          comm)
    {
      return CellModel(structure, setup, comm).sample();
    }



    const LevelSetMeshMotion &
    CellModel::motion() const
    {
      // Needs the mesh as made for `start`: gradient() and move_to() call
      // it before they move anything.
      if (!motion_)
        motion_ = std::make_unique<LevelSetMeshMotion>(*mesh,
                                                       Point<2>(L, L),
                                                       start.level_set());
      return *motion_;
    }



    void
    CellModel::write_vtu(const std::string &file_stem) const
    {
      cell->write_vtu(
        file_stem,
        {},
        [](const Point<2> &, const types::material_id) {
          return std::vector<double>();
        },
        design.cell_map());
    }



    void
    CellModel::write_outline(const std::string &file_name,
                             const double       side) const
    {
      const Tensor<2, 2>                              F = design.cell_map();
      std::vector<std::vector<std::array<double, 2>>> loops;
      for (const auto &loop : PolygonDomain::boundary_of(*mesh).loops)
        {
          auto &polygon = loops.emplace_back();
          for (const Point<2> &v : loop.vertices)
            {
              const Tensor<1, 2> x = (side / L) * (F * v);
              polygon.push_back({{x[0], x[1]}});
            }
          // Outer loops counter-clockwise, holes clockwise (F keeps the
          // orientation): cutters that ignore the even-odd rule fill by
          // the nonzero winding number, which then agrees.
          if ((signed_area(loop.vertices) < 0) != loop.hole)
            std::reverse(polygon.begin(), polygon.end());
        }
      if (std::filesystem::path(file_name).extension() == ".dxf")
        write_polygons_dxf(file_name, loops);
      else
        write_polygons_svg(file_name, loops, 1e-3 * side);
    }



    void
    CellModel::homogenize()
    {
      const ParallelogramCell parallelogram(design.cell_map());
      Timer                   timer;
      cell                  = std::make_unique<PeriodicHomogenization<2>>(comm,
                                                         *mesh,
                                                         Point<2>(L, L),
                                                         setup.solver,
                                                         setup.degree,
                                                         setup.symmetric_mesh);
      current.seconds_setup = timer.wall_time();
      timer.restart();
      const SymmetricTensor<4, 2> base =
        parallelogram.to_reference(setup.base.tensor());
      Sample &r = current;
      r.C_reference =
        cell
          ->homogenize(
            [&](const Point<2> &, const types::material_id) { return base; })
          .C;
      r.seconds_solve = timer.wall_time();
      r.C             = parallelogram.from_reference(r.C_reference);
      double area     = 0;
      for (const auto &c : mesh->active_cell_iterators())
        area += c->measure();
      r.mesh.area   = area;
      r.phi         = area / (L * L);
      r.fit         = isotropic_fit(r.C);
      r.orthotropic = orthotropic_moduli(r.C);
      r.anisotropy  = anisotropy(r.C);
      r.cells       = mesh->n_active_cells();
      r.vertices    = mesh->n_used_vertices();
      r.dofs        = cell->n_dofs();
    }



    CellModel::Gradient
    CellModel::gradient() const
    {
      using AD                 = Sacado::Fad::DFad<double>;
      constexpr unsigned int n = RhombicStructure::n_parameters;
      AssertThrow(design.p == start.p,
                  ExcMessage("CellModel::gradient() is available on the "
                             "structure that was meshed"));
      std::array<AD, n> p;
      for (unsigned int i = 0; i < n; ++i)
        p[i] = AD(n, i, design.p[i]);
      const auto         graph = design.graph<AD>(p);
      const Tensor<2, 2> F     = design.cell_map();
      // The level set is read on the reference square: phi(F x).
      const auto dphi_dp = [&](const Point<2> &x) {
        const AD            v = graph.value(Point<2>(F * x));
        std::vector<double> d(n);
        for (unsigned int i = 0; i < n; ++i)
          d[i] = v.dx(i);
        return d;
      };
      const auto              theta = motion().velocities(dphi_dp, n);
      const auto              dC_dX = cell->vertex_shape_gradient();
      const ParallelogramCell parallelogram(design.cell_map());
      Gradient                result;
      for (unsigned int i = 0; i < n; ++i)
        {
          SymmetricTensor<4, 2> d;
          for (unsigned int v = 0; v < dC_dX.size(); ++v)
            for (unsigned int k = 0; k < 2; ++k)
              if (theta[i][v][k] != 0)
                d += theta[i][v][k] * dC_dX[v][k];
          result.C[i] = parallelogram.from_reference(d);
          // d|omega| = sum_K |K| sum_v theta_v . grad lambda_v (P1 motion).
          double d_area = 0;
          for (const auto &c : mesh->active_cell_iterators())
            {
              const Point<2> x[3] = {c->vertex(0), c->vertex(1), c->vertex(2)};
              const double   twice_area = (x[1] - x[0])[0] * (x[2] - x[0])[1] -
                                        (x[1] - x[0])[1] * (x[2] - x[0])[0];
              for (unsigned int v = 0; v < 3; ++v)
                {
                  const Tensor<1, 2> a = x[(v + 2) % 3] - x[(v + 1) % 3];
                  // |K| grad lambda_v = +-rot(a) / 2 (the orientation's sign)
                  d_area += (twice_area > 0 ? 0.5 : -0.5) *
                            (theta[i][c->vertex_index(v)][0] * -a[1] +
                             theta[i][c->vertex_index(v)][1] * a[0]);
                }
            }
          result.phi[i] = d_area / (L * L);
        }
      return result;
    }



    void
    CellModel::move_to(const RhombicStructure &other)
    {
      AssertThrow(other.alpha == start.alpha &&
                    other.blending == start.blending,
                  ExcMessage("CellModel::move_to() keeps the cell's angle "
                             "and blending"));
      design = other;
      LevelSetMeshMotion::set_vertices(
        *mesh, motion().moved_vertices(other.level_set()));
      check_mesh_validity(*mesh,
                          "the rhombic cell mesh moved to the new design "
                          "(too large a step: remesh)");
      homogenize();
    }
  } // namespace rhombic
} // namespace forma
