// The rhombic family (thesis ch. 4.4, 4.10.1) and its homogenization:
//  - the level set has the rhombus's two reflection symmetries and the
//    cell's periodicity;
//  - derivatives of the level set with respect to p1..p8 by Sacado match
//    central differences (what shape derivatives will use);
//  - node 4's joint reaches the cell's corner and joins its image there
//    where corner_clearance() changes sign, and clear_corner() moves it
//    back;
//  - on the square cell, mirrored() (p1 <-> p2, p3 <-> p4, p7 <-> p8) is
//    the structure reflected across the bisector of the cell's sides
//    through its center, with the same isotropic fit and anisotropy;
//  - C^H is orthotropic in the diagonal axes (ch. 4.6.1) up to the mesh's
//    asymmetry, converges under mesh refinement, and the CLM transform
//    (eq. 4.11) agrees with a direct computation for another base
//    Poisson's ratio.

#include <forma/homogenization/bounds.h>
#include <forma/microstructure/rhombic_structure.h>
#include <forma/rhombic/study.h>

#include "../tests.h"
#include <Sacado.hpp>

using namespace dealii;
using namespace forma;

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();

  RhombicStructure s;
  s.alpha                  = M_PI / 3;
  s.p                      = {{0.2, 0.15, 0.3, 0.7, 0.25, 0.08, 0.1, 0.08}};
  const auto         graph = s.graph<double>(s.p);
  const Tensor<2, 2> F     = s.cell_map();

  // Symmetries (in R: reflections about the x and y axes through the
  // cell's center) and periodicity (on the reference square).
  {
    const Point<2> center(F * Point<2>(1, 1));
    double         asym = 0, aper = 0;
    for (unsigned int k = 0; k < 200; ++k)
      {
        const Point<2>     q(2.0 * ((k * 37) % 200) / 200,
                         2.0 * ((k * 91) % 200) / 200);
        const Point<2>     x(F * q);
        const Tensor<1, 2> d = x - center;
        const double       v = graph.value(x);
        asym                 = std::max(asym,
                        std::abs(v - graph.value(center +
                                                 Tensor<1, 2>({d[0], -d[1]}))));
        asym                 = std::max(asym,
                        std::abs(v - graph.value(center +
                                                 Tensor<1, 2>({-d[0], d[1]}))));
        const auto phi       = s.level_set();
        aper =
          std::max(aper,
                   std::abs(phi(Point<2>(0, q[1])) - phi(Point<2>(2, q[1]))));
        aper =
          std::max(aper,
                   std::abs(phi(Point<2>(q[0], 0)) - phi(Point<2>(q[0], 2))));
      }
    deallog << "reflection symmetry defect "
            << (asym < 1e-12 ? "< 1e-12" : "TOO LARGE")
            << ", periodicity defect " << (aper < 1e-9 ? "< 1e-9" : "TOO LARGE")
            << std::endl;
  }

  // Sacado derivatives against central differences.
  {
    using AD = Sacado::Fad::DFad<double>;
    std::array<AD, 8> p_ad;
    for (unsigned int i = 0; i < 8; ++i)
      p_ad[i] = AD(8, i, s.p[i]);
    const auto graph_ad = s.graph<AD>(p_ad);
    double     worst    = 0;
    for (unsigned int k = 0; k < 50; ++k)
      {
        const Point<2> x(F * Point<2>(0.2 + 1.6 * ((k * 13) % 50) / 50.,
                                      0.2 + 1.6 * ((k * 29) % 50) / 50.));
        const AD       v = graph_ad.value(x);
        for (unsigned int i = 0; i < 8; ++i)
          {
            const double h  = 1e-6;
            auto         pp = s.p, pm = s.p;
            pp[i] += h, pm[i] -= h;
            const double fd =
              (s.graph<double>(pp).value(x) - s.graph<double>(pm).value(x)) /
              (2 * h);
            worst = std::max(worst, std::abs(fd - v.dx(i)));
          }
      }
    deallog << "dphi/dp: Sacado vs central differences "
            << (worst < 1e-6 ? "< 1e-6" : "TOO LARGE") << std::endl;
  }

  // Node 4 at its corner: at 46.875 degrees with thin struts its joint
  // reaches the obtuse corner between p4 = 0.9 and 0.905 and joins its
  // image there: two more boundary loops, E nearly doubles (the full
  // map's sensitive spot). corner_clearance() changes sign there,
  // and clear_corner() moves node 4 back to the requested clearance.
  {
    RhombicStructure c;
    c.alpha              = 46.875 * M_PI / 180;
    c.p                  = {{0.1, 0.05, 0.5, 0.9, 0.3, 0.1, 0.05, 0.015}};
    const double at_09   = c.corner_clearance();
    c.p[3]               = 0.905;
    const double at_0905 = c.corner_clearance();
    deallog << "corner clearance at p4 = 0.9: "
            << (at_09 > 0.002 && at_09 < 0.004 ? "in (0.002, 0.004)" : "WRONG")
            << ", at 0.905: "
            << (at_0905 < -0.001 && at_0905 > -0.002 ? "in (-0.002, -0.001)" :
                                                       "WRONG")
            << std::endl;
    rhombic::Setup coarse;
    coarse.base               = IsotropicModuli::from_young_poisson(1, 0);
    coarse.mesh.size          = 0.05;
    coarse.mesh.boundary_size = 0.005;
    for (const double p4 : {0.88, 0.91})
      {
        c.p[3]       = p4;
        const auto r = rhombic::evaluate(c, coarse, MPI_COMM_WORLD);
        deallog << "p4 = " << p4 << ": corner clearance "
                << (c.corner_clearance() > 0 ? "positive" : "negative")
                << ", boundary loops " << r.mesh.boundary_loops << ", E/E_b "
                << rounded(r.fit.E, 2) << std::endl;
      }
    const double min   = RhombicStructure::min_corner_clearance;
    c.p[3]             = 0.905;
    const bool   moved = c.clear_corner(min, 0.1);
    const double left  = c.corner_clearance() - min;
    deallog << "clear_corner from 0.905: moved " << moved << ", p4 "
            << rounded(c.p[3], 4)
            << ", clearance - min in [0, 1e-6]: " << (left >= 0 && left <= 1e-6)
            << "; again: moved " << c.clear_corner(min, 0.1) << std::endl;

    // A square cell with thin struts has no primitive near the corner
    // (infinitely clear, nothing to move); node 3's thick joint at the
    // acute corner covers it as node 4's does at the obtuse one.
    RhombicStructure square;
    square.p = {{0.3, 0.3, 0.5, 0.5, 0.1, 0.1, 0.1, 0.1}};
    deallog << "square, thin struts: clearance infinite "
            << std::isinf(square.corner_clearance()) << ", moved "
            << square.clear_corner(min, 0.1);
    square.p = {{0.3, 0.3, 0.9, 0.5, 0.1, 0.1, 0.2, 0.1}};
    deallog << "; node 3 at 0.9 with radius 0.2: clearance negative "
            << (square.corner_clearance() < 0) << ", cleared by p4 "
            << square.clear_corner(min, 0.1) << std::endl;
  }

  // The mirror image on the square cell: the level set reflected across
  // the line x = y through the center (the sides' bisectors in R are at 45
  // degrees to the diagonal axes), and the same moduli.
  {
    RhombicStructure a;
    a.p = {{0.32, 0.24, 0.35, 0.72, 0.3, 0.08, 0.12, 0.05}};
    const RhombicStructure b  = a.mirrored();
    const auto             ga = a.graph<double>(a.p), gb = b.graph<double>(b.p);
    const Point<2>         center(a.cell_map() * Point<2>(1, 1));
    double                 defect = 0;
    for (unsigned int k = 0; k < 200; ++k)
      {
        const Tensor<1, 2> d(
          {2.0 * ((k * 37) % 200) / 200 - 1, 2.0 * ((k * 91) % 200) / 200 - 1});
        defect =
          std::max(defect,
                   std::abs(ga.value(center + d) -
                            gb.value(center + Tensor<1, 2>({d[1], d[0]}))));
      }
    rhombic::Setup m;
    m.base               = IsotropicModuli::from_young_poisson(1, 0);
    m.mesh.size          = 0.05;
    m.mesh.boundary_size = 0.0125;
    const auto ra        = rhombic::evaluate(a, m, MPI_COMM_WORLD);
    const auto rb        = rhombic::evaluate(b, m, MPI_COMM_WORLD);
    deallog << "mirrored on the square: p = " << b.p[0] << ", " << b.p[1]
            << ", " << b.p[2] << ", " << b.p[3] << ", " << b.p[4] << ", "
            << b.p[5] << ", " << b.p[6] << ", " << b.p[7]
            << "; level set reflected (< 1e-12): " << (defect < 1e-12)
            << "; |E_b / E_a - 1| < 0.005: "
            << (std::abs(rb.fit.E / ra.fit.E - 1) < 0.005)
            << ", |nu_b - nu_a| < 0.003: "
            << (std::abs(rb.fit.nu - ra.fit.nu) < 0.003)
            << ", |a2_b - a2_a| < 0.01: "
            << (std::abs(rb.anisotropy.a2 - ra.anisotropy.a2) < 0.01)
            << ", |phi_b - phi_a| < 1e-3: "
            << (std::abs(rb.phi - ra.phi) < 1e-3) << std::endl;
  }

  // Homogenization: orthotropy, convergence, CLM.
  rhombic::Setup setup;
  setup.base = IsotropicModuli::from_young_poisson(1, 0);
  std::vector<SymmetricTensor<4, 2>> C;
  for (const double h : {0.1, 0.05, 0.025})
    {
      setup.mesh.size          = h;
      setup.mesh.boundary_size = h / 2;
      const auto r             = rhombic::evaluate(s, setup, MPI_COMM_WORLD);
      C.push_back(r.C);
      const VoigtMatrix V = to_voigt(r.C);
      deallog << "h = " << h << ": E1 in [0.04, 0.05]: "
              << (r.orthotropic.E1 > 0.04 && r.orthotropic.E1 < 0.05)
              << ", nu12 in [1.1, 1.25]: "
              << (r.orthotropic.nu12 > 1.1 && r.orthotropic.nu12 < 1.25)
              << ", phi = " << rounded(r.phi, 3) << ", shear coupling "
              << (std::hypot(V[0][2], V[1][2]) < 1e-3 * V.norm() ?
                    "< 1e-3 |C|" :
                    "TOO LARGE")
              << std::endl;
    }
  const double e1 = (C[0] - C[2]).norm() / C[2].norm(),
               e2 = (C[1] - C[2]).norm() / C[2].norm();
  deallog << "refinement: |C_h - C_h/4| / |C| "
          << (e1 < 0.1 ? "< 0.1" : "TOO LARGE") << ", |C_h/2 - C_h/4| / |C| "
          << (e2 < 0.3 * e1 ? "< 0.3 of it" : "NOT SMALLER") << std::endl;

  // CLM: base nu 0 -> 0.3 against a direct computation.
  {
    const auto to    = IsotropicModuli::from_young_poisson(1, 0.3);
    const auto C_clm = clm_transform(C[2], setup.base, to);
    setup.base       = to;
    const auto r     = rhombic::evaluate(s, setup, MPI_COMM_WORLD);
    deallog << "CLM vs direct for base nu = 0.3: |C_clm - C| / |C| "
            << ((C_clm - r.C).norm() / r.C.norm() < 2e-3 ? "< 2e-3" :
                                                           "TOO LARGE")
            << std::endl;
  }
}
