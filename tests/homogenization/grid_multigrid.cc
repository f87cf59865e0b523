// GridMultigridHomogenization solves the same Q1 problem as
// PeriodicHomogenization's direct solver on a regular grid: C^H agrees to
// 1e-8 on random two-phase images (contrast 1e-3, even and odd grid sizes,
// non-square pixels), on a chiral family structure and a limit structure,
// and so do the material derivatives. The limit structure's joints are
// rank-one laminates with void, stiff along the layers only: that
// anisotropy defeats point smoothing, and CG needs several hundred steps
// there (printed as "over 100", a known limit).

#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/grid_multigrid.h>
#include <forma/homogenization/periodic_homogenization.h>
#include <forma/microstructure/hexagonal_laminate.h>
#include <forma/microstructure/pixel_material.h>

#include "../tests.h"

using namespace dealii;
using namespace forma;

namespace
{
  SymmetricTensor<4, 2>
  isotropic(const double E, const double nu)
  {
    const auto m =
      IsotropicModuli::of_material(E, nu, PlaneModel::plane_stress);
    SymmetricTensor<4, 2> C;
    for (unsigned int i = 0; i < 2; ++i)
      for (unsigned int j = 0; j < 2; ++j)
        for (unsigned int k = 0; k < 2; ++k)
          for (unsigned int l = 0; l < 2; ++l)
            C[i][j][k][l] = (m.kappa - m.mu) * (i == j) * (k == l) +
                            m.mu * ((i == k) * (j == l) + (i == l) * (j == k));
    return C;
  }

  /// Compare the two engines on pixel tensors (pixel i + nx j).
  void
  compare(const std::string                        &name,
          const Point<2>                           &size,
          const unsigned int                        nx,
          const unsigned int                        ny,
          const std::vector<SymmetricTensor<4, 2>> &pixels,
          const unsigned int                        coarsest_nodes     = 256,
          const bool                                operator_dependent = true)
  {
    PeriodicHomogenization<2>::SolverParameters sp;
    sp.type = "direct";
    PeriodicHomogenization<2> direct(MPI_COMM_SELF, size, {{nx, ny}}, sp);
    const auto material = [&](const Point<2> &x, const types::material_id) {
      const unsigned int i =
        std::min<unsigned int>(nx - 1, x[0] / size[0] * nx);
      const unsigned int j =
        std::min<unsigned int>(ny - 1, x[1] / size[1] * ny);
      return pixels[i + nx * j];
    };
    const auto C_direct = direct.homogenize(material).C;

    // A tight tolerance: the material derivative's error is first order in
    // the solver's (C^H's about second order).
    GridMultigridHomogenization::Parameters p;
    p.tolerance          = 1e-10;
    p.coarsest_nodes     = coarsest_nodes;
    p.operator_dependent = operator_dependent;
    GridMultigridHomogenization mg(size, {{nx, ny}}, p);
    const auto                  r = mg.homogenize(pixels);
    const double       error      = (r.C - C_direct).norm() / C_direct.norm();
    const unsigned int most       = r.iterations;
    dealii::deallog << name << " (" << nx << " x " << ny << ", "
                    << mg.levels().size()
                    << " levels): E = " << rounded(isotropic_fit(C_direct).E)
                    << ", |C_mg - C_direct| / |C| "
                    << (error < 1e-8 ? "< 1e-8" : "LARGE") << ", CG steps "
                    << (most <= 100 ? "<= 100" : "over 100") << std::endl;

    // d/dq of C^H for dC/dq = the pixel's own tensor on the left half.
    std::vector<std::vector<SymmetricTensor<4, 2>>> dC(pixels.size());
    for (unsigned int j = 0; j < ny; ++j)
      for (unsigned int i = 0; i < nx; ++i)
        dC[i + nx * j] = {2 * i < nx ? pixels[i + nx * j] :
                                       SymmetricTensor<4, 2>()};
    const auto g_mg     = mg.material_gradient(dC)[0];
    const auto g_direct = direct.material_gradient(
      [&](const Point<2> &x, const types::material_id) {
        const unsigned int i =
          std::min<unsigned int>(nx - 1, x[0] / size[0] * nx);
        const unsigned int j =
          std::min<unsigned int>(ny - 1, x[1] / size[1] * ny);
        return dC[i + nx * j];
      },
      1)[0];
    const double g_error = (g_mg - g_direct).norm() / g_direct.norm();
    dealii::deallog << "  material derivative: relative difference "
                    << (g_error < 1e-8 ? "< 1e-8" : "LARGE") << std::endl;
  }

  std::vector<SymmetricTensor<4, 2>>
  random_image(const unsigned int nx, const unsigned int ny, unsigned int seed)
  {
    const auto stiff = isotropic(1, 0.3), soft = isotropic(1e-3, 0.3);
    std::vector<SymmetricTensor<4, 2>> pixels(nx * ny);
    for (auto &p : pixels)
      {
        seed = 1103515245u * seed + 12345u;
        p    = ((seed >> 16) % 100 < 55) ? stiff : soft;
      }
    return pixels;
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  compare(
    "random, square pixels", Point<2>(1, 1), 64, 64, random_image(64, 64, 1));
  compare(
    "random, odd sizes", Point<2>(1.3, 0.7), 37, 23, random_image(37, 23, 2));
  compare(
    "random, two cells high", Point<2>(1, 0.1), 40, 2, random_image(40, 2, 3));

  // Small grids coarsened as far as allowed (16 nodes): odd sizes, and
  // grids one or two cells high, with both interpolations.
  for (const bool od : {true, false})
    for (const auto &[nx, ny] :
         std::vector<std::pair<unsigned int, unsigned int>>{{9, 5},
                                                            {40, 2},
                                                            {12, 3}})
      compare(std::string("tiny grids, ") +
                (od ? "operator-dependent" : "bilinear"),
              Point<2>(1, 0.6),
              nx,
              ny,
              random_image(nx, ny, nx + ny),
              16,
              od);

  const unsigned int ny = 30, nx = 52;
  const double W = HexagonalLaminate::width, H = HexagonalLaminate::height;
  const auto   base =
    IsotropicModuli::of_material(1, 0.2, PlaneModel::plane_stress);
  const auto weak =
    IsotropicModuli::from_bulk_shear(1e-6 * base.kappa, 1e-6 * base.mu);
  std::vector<HexagonalLaminate> structures(2);
  structures[0].family = HexagonalLaminate::Family::triangle;
  structures[0].p1 = 0.7, structures[0].p2 = 1, structures[0].p3 = 0.3,
  structures[0].p4    = 0.6;
  structures[1].limit = true, structures[1].p1 = 0.75,
  structures[1].theta = 0.8, structures[1].alpha = 0.3;
  for (const auto &s : structures)
    {
      const auto material =
        pixel_material(s, base, weak, GrayPixels::hashin_shtrikman, nx, ny);
      std::vector<SymmetricTensor<4, 2>> pixels(nx * ny);
      for (unsigned int j = 0; j < ny; ++j)
        for (unsigned int i = 0; i < nx; ++i)
          pixels[i + nx * j] =
            material(Point<2>((i + 0.5) * W / nx, (j + 0.5) * H / ny), 0);
      compare(s.family_name() + (s.limit ? " limit" : ""),
              Point<2>(W, H),
              nx,
              ny,
              pixels);
    }

  expect_refusal(
    "a void pixel without a weak phase",
    [] {
      GridMultigridHomogenization mg(Point<2>(1, 1), {{4, 4}}, {});
      auto                        pixels = random_image(4, 4, 1);
      pixels[5]                          = SymmetricTensor<4, 2>();
      mg.homogenize(pixels);
    },
    "pixel (1, 1) is not positive definite");
  expect_refusal(
    "material_gradient() before homogenize()",
    [] {
      GridMultigridHomogenization mg(Point<2>(1, 1), {{4, 4}}, {});
      mg.material_gradient({});
    },
    "needs a homogenize() first");
  expect_refusal(
    "12 tensors for a 4 x 4 grid",
    [] {
      GridMultigridHomogenization mg(Point<2>(1, 1), {{4, 4}}, {});
      mg.homogenize(random_image(4, 3, 1));
    },
    "12 pixel tensors for a grid of 16 pixels");
}
