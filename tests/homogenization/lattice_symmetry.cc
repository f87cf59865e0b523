// The symmetry reductions of PeriodicHomogenization on regular grids give
// the same C^H as the whole rectangle: the primitive half of the sqrt(3) x 1
// cell with the hexagonal lattice's shift, odd fluctuations about a lattice
// point (rotation by pi), and both, for chiral Hexagon and Triangle
// structures and a limit structure (anisotropic laminate phases). A
// material without the rotation symmetry shows that the odd-fluctuation
// constraints are active: there they change C^H.

#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/periodic_homogenization.h>
#include <forma/microstructure/hexagonal_laminate.h>
#include <forma/microstructure/pixel_material.h>

#include "../tests.h"

using namespace dealii;
using namespace forma;

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  const unsigned int ny = 30, nx = 52; // round(sqrt(3) 30), both even
  const double W = HexagonalLaminate::width, H = HexagonalLaminate::height;
  const auto   base =
    IsotropicModuli::of_material(1, 0.2, PlaneModel::plane_stress);
  const auto weak =
    IsotropicModuli::from_bulk_shear(1e-6 * base.kappa, 1e-6 * base.mu);

  std::vector<HexagonalLaminate> structures(3);
  structures[0].family = HexagonalLaminate::Family::hexagon;
  structures[0].p1 = 0.8, structures[0].p2 = 0.4, structures[0].p3 = 0.5,
  structures[0].p4     = 0.7;
  structures[1].family = HexagonalLaminate::Family::triangle;
  structures[1].p1 = 0.7, structures[1].p2 = 1, structures[1].p3 = 0.3,
  structures[1].p4    = 0.6;
  structures[2].limit = true, structures[2].p1 = 0.75,
  structures[2].theta = 0.8, structures[2].alpha = 0;

  PeriodicHomogenization<2>::SolverParameters sp;
  PeriodicHomogenization<2>::GridLattice      odd, shifted, both;
  odd.inversion  = true;
  shifted.shift  = Tensor<1, 2>({0., H / 2});
  both           = shifted;
  both.inversion = true;
  PeriodicHomogenization<2> rectangle(MPI_COMM_SELF,
                                      Point<2>(W, H),
                                      {{nx, ny}},
                                      sp);
  PeriodicHomogenization<2> rectangle_odd(
    MPI_COMM_SELF, Point<2>(W, H), {{nx, ny}}, sp, 1, odd);
  PeriodicHomogenization<2> half(
    MPI_COMM_SELF, Point<2>(W / 2, H), {{nx / 2, ny}}, sp, 1, shifted);
  PeriodicHomogenization<2> half_odd(
    MPI_COMM_SELF, Point<2>(W / 2, H), {{nx / 2, ny}}, sp, 1, both);
  deallog << "unknowns: rectangle " << rectangle.n_dofs() << ", half "
          << half.n_dofs() << std::endl;

  for (const auto &s : structures)
    {
      const auto material =
        pixel_material(s, base, weak, GrayPixels::hashin_shtrikman, nx, ny);
      const auto C = rectangle.homogenize(std::cref(material)).C;
      deallog << s.family_name() << (s.limit ? " limit" : "")
              << ": E = " << rounded(isotropic_fit(C).E)
              << ", nu = " << rounded(isotropic_fit(C).nu) << std::endl;
      for (const auto &[name, cell] :
           std::vector<std::pair<const char *, PeriodicHomogenization<2> *>>{
             {"odd fluctuations", &rectangle_odd},
             {"primitive half", &half},
             {"both", &half_odd}})
        {
          const auto   Cs    = cell->homogenize(std::cref(material)).C;
          const double error = (Cs - C).norm() / C.norm();
          deallog << "  " << name << ": |C - C_rectangle| / |C| "
                  << (error < 1e-10 ? "< 1e-10" : "LARGE") << std::endl;
        }
    }

  // An off-center inclusion: not symmetric under the rotation by pi.
  const auto lopsided = [&](const Point<2> &x, const types::material_id) {
    return (x - Point<2>(0.3, 0.3)).norm() < 0.2 ? weak.tensor() :
                                                   base.tensor();
  };
  const auto C  = rectangle.homogenize(lopsided).C;
  const auto Cs = rectangle_odd.homogenize(lopsided).C;
  deallog << "unsymmetric material, odd fluctuations: C^H changes by more "
             "than 1e-3: "
          << ((Cs - C).norm() / C.norm() > 1e-3 ? "yes" : "NO") << std::endl;
}
