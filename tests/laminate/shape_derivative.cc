// The shape derivative behind thesis Table 5.1: J = 1/2 |S^H - S*|^2 (S the
// compliance, S* that of an isotropic target on the HS bound) and its
// derivative with respect to the positions of the vertices on the
// solid-void interface of a conforming periodic mesh. Taylor tests
// (|J(x + h d) - J(x) - h dJ d| must fall as h^2): J against C^H along a
// random symmetric direction, and J against the interface vertices moved
// along a random field on a Hexagon structure's mesh (P1 and P2).

#include <deal.II/grid/tria.h>

#include <forma/laminate/shape_derivative.h>
#include <forma/laminate/study.h>
#include <forma/microstructure/pixel_material.h>

#include "../tests.h"

#include <cmath>
#include <iomanip>
#include <random>

using namespace dealii;
using namespace forma;

namespace
{
  // Errors e(h) for h = 1e-2 / 2^k, k = 0..3, as rate verdicts.
  void
  report_rates(const std::function<double(double)> &error)
  {
    double previous = 0;
    for (unsigned int k = 0; k < 4; ++k)
      {
        const double e = error(1e-2 / std::pow(2., k));
        if (k > 0)
          deallog << "  rate " << rate_verdict(std::log2(previous / e))
                  << std::endl;
        previous = e;
      }
  }

  void
  misfit_taylor()
  {
    const laminate::ComplianceMisfit misfit(0.5, -0.5);
    SymmetricTensor<4, 2> C = IsotropicModuli::from_young_poisson(0.2, 0.1)
                                .tensor(),
                          dC;
    std::mt19937                           rng(3);
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = i; j < 3; ++j)
        {
          // Voigt pairs (0,0), (1,1), (0,1); C and dC keep the major
          // symmetry of elasticity tensors.
          const unsigned int a[3][2] = {{0, 0}, {1, 1}, {0, 1}};
          const double       c = u(rng), dc = 20 * u(rng);
          const unsigned int p = a[i][0], q = a[i][1], r = a[j][0], t = a[j][1];
          C[p][q][r][t] += c;
          dC[p][q][r][t] = dc;
          if (i != j)
            C[r][t][p][q] += c, dC[r][t][p][q] = dc;
        }
    const double J  = misfit.value(C);
    const double dJ = full_contraction(misfit.derivative(C), dC);
    deallog << "compliance misfit against C^H" << std::endl;
    report_rates([&](const double h) {
      return std::abs(misfit.value(C + h * dC) - J - h * dJ);
    });
  }

  void
  shape_taylor(const unsigned int degree)
  {
    HexagonalLaminate s;
    s.p1 = 0.75, s.p2 = 0.3, s.p3 = 0.5, s.p4 = 0.6;
    const IsotropicModuli base = IsotropicModuli::from_young_poisson(1, 0),
                          weak = IsotropicModuli::from_young_poisson(1e-6, 0);
    Triangulation<2> mesh;
    laminate::conforming_mesh(s, 0.06, mesh);
    std::vector<double> density;
    const auto          phases = phase_tensors(s, base, weak, density);
    const laminate::ComplianceMisfit            misfit(0.5, -0.5);
    PeriodicHomogenization<2>::SolverParameters solver;
    solver.type  = "direct";
    const auto d = laminate::interface_shape_derivative(
      mesh, phases, weak.tensor(), solver, degree, misfit);
    deallog << "P" << degree << ": " << d.vertices.size()
            << " interface vertices, |dJ/dX| > 0: "
            << (d.norm > 0 ? "yes" : "no") << std::endl;
    std::mt19937                           rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    std::vector<Tensor<1, 2>>              theta(d.vertices.size());
    double                                 dJ = 0;
    for (unsigned int i = 0; i < theta.size(); ++i)
      {
        theta[i][0] = u(rng), theta[i][1] = u(rng);
        dJ += d.derivative[i] * theta[i];
      }
    const auto original = mesh.get_vertices();
    report_rates([&](const double h) {
      // Move the interface vertices by h * theta * (a tenth of a cell).
      std::vector<bool> moved(mesh.n_vertices(), false);
      std::vector<int>  slot(mesh.n_vertices(), -1);
      for (unsigned int i = 0; i < d.vertices.size(); ++i)
        slot[d.vertices[i]] = i;
      for (const auto &c : mesh.active_cell_iterators())
        for (const unsigned int v : c->vertex_indices())
          {
            const unsigned int g = c->vertex_index(v);
            if (moved[g])
              continue;
            moved[g]     = true;
            c->vertex(v) = original[g];
            if (slot[g] >= 0)
              c->vertex(v) += 0.1 * h * theta[slot[g]];
          }
      const auto e = laminate::interface_shape_derivative(
        mesh, phases, weak.tensor(), solver, degree, misfit);
      return std::abs(e.J - d.J - 0.1 * h * dJ);
    });
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  initlog();
  misfit_taylor();
  shape_taylor(1);
  shape_taylor(2);
}
