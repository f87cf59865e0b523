// Thesis Table 5.2 under the reading of doc/laminate.md ("Table 5.2 row by
// row"): the thesis's Hexagon is forma's `triangle` family, its Triangle
// forma's `hexagon`, and forma's p3 is the thesis's p2 * p3. The three
// Hexagon rows (straight beams, nothing fitted) and the second Triangle row
// (beam shift 0.3514 of the joint width, fitted once to E on a finer mesh)
// on a coarse conforming P2 mesh (element size 0.025) must land within 4%
// of the thesis's E and 0.025 of its nu (Unstr. columns); the read-as-named
// Hexagon row 1 must not (E 0.596, nu 0.123). Last, a structure with steep
// beams whose periodic images meet a side 4e-6 apart, which the periodic
// mesher once refused as "not periodic", must mesh, and one whose clipped
// beams leave slivers on one side only (once dropped there, breaking the
// match with the other side).

#include "../tests.h"
#include <nlohmann/json.hpp>

#include <cmath>

namespace
{
  void
  row(const std::string &name,
      const std::string &family,
      const double       p1,
      const double       p2,
      const double       p3,
      const double       p4,
      const double       E_thesis,
      const double       nu_thesis)
  {
    std::ostringstream prm;
    prm << "set Output directory = " << name << "\n"
        << "set Mode = compare meshes\n"
        << "subsection Base material\n set Poisson's ratio = 0\nend\n"
        << "subsection Grid\n set Cells along height = 12\nend\n"
        << "subsection Structure\n set Type = " << family
        << "\n set p1 = " << p1 << "\n set p2 = " << p2 << "\n set p3 = " << p3
        << "\n set p4 = " << p4 << "\nend\n"
        << "subsection Conforming mesh\n set Element size = 0.025\nend\n"
        << "subsection Output\n set Write vtu = false\nend\n";
    const int code = run_app(FORMA_APP, name, prm.str());
    if (E_thesis < 1e-3) // only whether it meshes and runs
      {
        dealii::deallog << name << " (" << family << "): exit code " << code
                        << std::endl;
        return;
      }
    const auto   s  = nlohmann::json::parse(read_file(name + "/summary.json"));
    const double E  = s["conforming_mesh"]["result"]["E"];
    const double nu = s["conforming_mesh"]["result"]["nu"];
    const bool   close =
      std::abs(E / E_thesis - 1) <= 0.04 && std::abs(nu - nu_thesis) <= 0.025;
    // The values themselves (0.364/0.477, 0.307/0.465, 0.682/0.170,
    // 0.0770/-0.735, 0.596/0.123) sit too near rounding edges to print.
    dealii::deallog << name << " (" << family << "): exit code " << code
                    << ", within 4% of E = " << E_thesis
                    << " and 0.025 of nu = " << nu_thesis << ": "
                    << (close ? "yes" : "no") << std::endl;
  }
} // namespace

int
main()
{
  initlog();
  row("hexagon_1", "triangle", 0.75, 0, 0.1, 0.74, 0.3554, 0.4873);
  row("hexagon_2", "triangle", 0.74, 0, 0.2, 0.526, 0.3123, 0.4500);
  row("hexagon_3", "triangle", 0.88, 0, 0.1, 0.642, 0.6845, 0.1656);
  row("triangle_2", "hexagon", 0.84, 0.3514, 0.13, 0.769, 0.0759, -0.7375);
  row("hexagon_1_as_named", "hexagon", 0.75, 0.1, 1, 0.74, 0.3554, 0.4873);
  // Only the exit code matters here (E/E_b is about 4e-4).
  row("steep_beams", "hexagon", 0.84, 0.9, 0.13, 0.769, 4e-4, -0.98);
  row("steep_beams_slivers", "hexagon", 0.9, 0.37, 1. / 6, 0.8, 4e-4, -0.9);
}
