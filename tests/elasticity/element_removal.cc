// The ESO-like cell selection (forma/elasticity/element_removal.h) on an
// 8 x 4 beam, clamped at x = 0 (id 0, the holding id), loaded at x = 2
// (id 1), free top and bottom (id 2, the holes' id), with stress fields
// whose outcome is known by hand:
// - bending (|y - 1/2|): the two middle rows go except the end columns,
//   which touch the clamp and the load: 12 cells;
// - both ends held, a stressed blob in the low-stress middle that touches
//   only the free bottom: it would float, so it goes with the rest (24);
// - low stress across two whole columns: the loaded end would be cut off
//   from the clamp, so both columns come back (0);
// - two low-stress 2 x 2 blocks, from the top and from the bottom, meeting
//   at one vertex: the kept cells there would touch through the vertex
//   alone, so the block cells at that vertex come back (6).

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include <forma/elasticity/element_removal.h>

#include "../tests.h"

#include <functional>
#include <set>

using namespace dealii;

void
run(const std::string                             &name,
    const Triangulation<2>                        &tria,
    const std::function<double(const Point<2> &)> &stress,
    const double                                   ratio,
    const std::set<types::boundary_id>            &holding = {0})
{
  std::vector<double> s(tria.n_active_cells());
  for (const auto &cell : tria.active_cell_iterators())
    s[cell->active_cell_index()] = stress(cell->center());
  const auto removed =
    forma::select_low_stress_cells(tria, s, ratio, 2, holding);
  unsigned int n = 0;
  std::string  map;
  // Rows from the top, 1 = removed.
  for (int j = 3; j >= 0; --j)
    {
      map += "\n  ";
      for (int i = 0; i < 8; ++i)
        for (const auto &cell : tria.active_cell_iterators())
          if (std::abs(cell->center()[0] - (0.125 + 0.25 * i)) < 1e-9 &&
              std::abs(cell->center()[1] - (0.125 + 0.25 * j)) < 1e-9)
            map += removed[cell->active_cell_index()] ? '1' : '0';
    }
  for (const bool r : removed)
    n += r;
  dealii::deallog << name << ": " << n << " cells removed" << map << std::endl;
}

int
main()
{
  initlog();
  Triangulation<2> tria;
  GridGenerator::subdivided_hyper_rectangle(
    tria, {8, 4}, Point<2>(0, 0), Point<2>(2, 1), true);
  // colorize: x = 0 -> 0, x = 2 -> 1, y = 0 -> 2, y = 1 -> 3; top free too.
  for (const auto &face : tria.active_face_iterators())
    if (face->at_boundary() && face->boundary_id() == 3)
      face->set_boundary_id(2);

  run(
    "bending",
    tria,
    [](const Point<2> &p) { return std::abs(p[1] - 0.5); },
    0.6);
  run("floating blob",
      tria,
      [](const Point<2> &p) {
        const bool ends = p[0] < 0.25 || p[0] > 1.75;
        const bool blob = std::abs(p[0] - 1) < 0.25 && p[1] < 0.5;
        return ends ? 1. : blob ? 0.9 : 0.01;
      },
      0.35,
      {0, 1});
  run(
    "cut-off load",
    tria,
    [](const Point<2> &p) { return std::abs(p[0] - 1) < 0.25 ? 0.01 : 1.; },
    0.3);
  run(
    "pinch",
    tria,
    [](const Point<2> &p) {
      const bool a = p[0] > 0.5 && p[0] < 1 && p[1] > 0.5; // from the top
      const bool b = p[0] > 1 && p[0] < 1.5 && p[1] < 0.5; // from the bottom
      return a || b ? 0.001 : 1.;
    },
    0.5);
}
