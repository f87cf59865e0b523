// Quad-to-rhombic mesh optimization (thesis ch. 4.7): the rhombus fit is
// exact on rhombi whatever their placement and positive otherwise; a mesh
// of rhombi is a fixed point; a jittered grid and a trapezoid strip become
// rhombic while their boundary stays where it was.

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <forma/rhombic/quad_mesh_optimization.h>

#include "../tests.h"

using namespace dealii;
using namespace forma::rhombic;

namespace
{
  constexpr double degrees = 180 / M_PI;

  void
  report(const std::string &name, const QuadMeshOptimizationResult &r)
  {
    deallog << name << ": rhombic error mean " << r.before.mean_error << " -> "
            << r.after.mean_error << ", max " << r.before.max_error << " -> "
            << r.after.max_error << "; alpha min "
            << r.before.min_alpha * degrees << " -> "
            << r.after.min_alpha * degrees << "; boundary deviation "
            << (r.boundary_deviation < 1e-2 ?
                  "< 1e-2" :
                  std::to_string(r.boundary_deviation))
            << " edge lengths; valid " << (r.after.min_scaled_jacobian > 0)
            << std::endl;
  }
} // namespace

int
main()
{
  initlog(3);

  // A 60 degree rhombus of side 1.3, turned by 25 degrees and moved.
  {
    const double       a = M_PI / 3, t = 25 / degrees, l = 1.3;
    const Tensor<1, 2> e1({l * std::cos(t), l * std::sin(t)}),
      e2({l * std::cos(t + a), l * std::sin(t + a)});
    const Point<2>   o(0.4, -2);
    const RhombicFit r = fit_rhombus({{o, o + e1, o + e2, o + e1 + e2}});
    deallog << "rhombus: angle " << r.angle * degrees << ", alpha "
            << r.alpha * degrees << ", area " << r.area << ", error "
            << (r.error < 1e-12 ? "< 1e-12" : "too large") << std::endl;
    // The same with the obtuse angle at vertex 0.
    const RhombicFit r2 = fit_rhombus({{o + e1, o + e1 + e2, o, o + e2}});
    deallog << "obtuse first: angle " << r2.angle * degrees << ", alpha "
            << r2.alpha * degrees << ", error "
            << (r2.error < 1e-12 ? "< 1e-12" : "too large") << std::endl;
    // A trapezoid is not a rhombus.
    const RhombicFit r3 = fit_rhombus(
      {{Point<2>(0, 0), Point<2>(2, 0), Point<2>(0.5, 1), Point<2>(1.5, 1)}});
    deallog << "trapezoid: alpha " << r3.alpha * degrees << ", error "
            << r3.error << std::endl;
  }

  QuadMeshOptimizationParameters prm;

  // A mesh of 70 degree rhombi does not move.
  {
    Triangulation<2>                  tria;
    const double                      a     = 70 / degrees;
    const std::array<Tensor<1, 2>, 2> edges = {
      {Tensor<1, 2>({4., 0.}),
       Tensor<1, 2>({3 * std::cos(a), 3 * std::sin(a)})}};
    GridGenerator::subdivided_parallelepiped<2, 2>(tria,
                                                   Point<2>(),
                                                   edges,
                                                   {4, 3});
    const auto before = tria.get_vertices();
    const auto r      = optimize_rhombic_mesh(tria, prm);
    double     moved  = 0;
    for (unsigned int v = 0; v < before.size(); ++v)
      moved = std::max(moved, before[v].distance(tria.get_vertices()[v]));
    deallog << "rhombic mesh: largest vertex move "
            << (moved < 1e-12 ? "< 1e-12" : "too large") << ", alpha "
            << r.after.min_alpha * degrees << std::endl;
  }

  // A square grid with its interior vertices jittered.
  {
    Triangulation<2> tria;
    GridGenerator::subdivided_hyper_cube(tria, 6);
    for (auto &cell : tria.active_cell_iterators())
      for (unsigned int v = 0; v < 4; ++v)
        {
          Point<2> &p = cell->vertex(v);
          if (p[0] > 1e-9 && p[0] < 1 - 1e-9 && p[1] > 1e-9 && p[1] < 1 - 1e-9)
            {
              // Deterministic, not random: the same jitter on every
              // machine; visited several times, so set from the grid point.
              const double gx = std::round(p[0] * 6), gy = std::round(p[1] * 6);
              p = Point<2>(gx / 6 + 0.04 * std::sin(3 * gx + 7 * gy),
                           gy / 6 + 0.04 * std::cos(5 * gx - 2 * gy));
            }
        }
    report("jittered grid", optimize_rhombic_mesh(tria, prm));
  }

  // A disk of quads with irregular vertices (valence 3 where the central
  // square meets the ring): not every quad can be a rhombus, the
  // optimization brings them closer while the vertices stay on the circle.
  {
    Triangulation<2> tria;
    GridGenerator::hyper_ball(tria);
    tria.refine_global(2);
    Triangulation<2> flat;
    GridGenerator::flatten_triangulation(tria, flat);
    const auto r = optimize_rhombic_mesh(flat, prm);
    report("disk", r);
    double off = 0;
    for (const auto &cell : flat.active_cell_iterators())
      for (const unsigned int f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          for (unsigned int v = 0; v < 2; ++v)
            off = std::max(off, std::abs(cell->face(f)->vertex(v).norm() - 1));
    deallog << "disk: largest distance of a boundary vertex from the circle "
            << (off < 0.02 ? "< 0.02" : std::to_string(off)) << std::endl;
  }

  // The same disk with an angle floor of 66 degrees (the thesis's disk):
  // every fitted angle reaches it, the boundary stays on the circle, and a
  // floor below every quad's angle changes nothing.
  {
    Triangulation<2> tria;
    GridGenerator::hyper_ball(tria);
    tria.refine_global(2);
    Triangulation<2> flat, same;
    GridGenerator::flatten_triangulation(tria, flat);
    same.copy_triangulation(flat);
    QuadMeshOptimizationParameters floored = prm;
    floored.angle_floor                    = 66 / degrees;
    const auto r = optimize_rhombic_mesh(flat, floored);
    report("disk, floor 66", r);
    deallog << "disk, floor 66: every alpha at least 66 - 0.01 degrees: "
            << (r.after.min_alpha * degrees > 66 - 0.01) << std::endl;
    floored.angle_floor = 40 / degrees;
    const auto r40      = optimize_rhombic_mesh(same, floored);
    deallog << "disk, floor 40 (below every quad): alpha min "
            << r40.after.min_alpha * degrees << ", rhombic error mean "
            << r40.after.mean_error << std::endl;
  }

  // Inverted input is refused.
  {
    Triangulation<2> tria;
    GridGenerator::hyper_cube(tria);
    tria.begin_active()->vertex(3) = Point<2>(-0.5, -0.5);
    try
      {
        optimize_rhombic_mesh(tria, prm);
      }
    catch (const std::exception &e)
      {
        std::string what = e.what();
        deallog << "inverted: "
                << (what.find("inverted") != std::string::npos ? "refused" :
                                                                 what)
                << std::endl;
      }
  }
}
