// Adaptive refinement of periodic cells with corners (issue 46, items 5 and
// 6d): C^H_11 of a square cell with a rectangular hole, Q1 and Q2, on
// uniform grids (8^2 ... 512^2 Q1, 8^2 ... 256^2 Q2) and on an 8 x 8 grid
// refined by PeriodicHomogenization::refine() (stress jumps, 20% of the
// cells per cycle). The reference is the adaptive Q2 run's limit (its last
// value less the geometric tail of its decrements). Prints CSV: cell,
// degree, strategy, unknowns, C11, relative error.

#include <forma/homogenization/elastic_tensor.h>
#include <forma/homogenization/periodic_homogenization.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <vector>

using namespace dealii;
using namespace forma;

namespace
{
  SymmetricTensor<4, 2>
  holed(const Point<2> &x, const types::material_id)
  {
    static const auto solid =
      IsotropicModuli::of_material(1.0, 0.3, PlaneModel::plane_strain);
    static const auto hole =
      IsotropicModuli::of_material(1e-4, 0.3, PlaneModel::plane_strain);
    const bool inside =
      std::abs(x[0] - 0.5) < 0.25 && std::abs(x[1] - 0.5) < 0.125;
    return inside ? hole.tensor() : solid.tensor();
  }

  struct Row
  {
    unsigned int degree;
    std::string  strategy;
    double       unknowns, c11;
  };

  PeriodicHomogenization<2>
  grid(const unsigned int n, const unsigned int degree)
  {
    PeriodicHomogenization<2>::SolverParameters sp;
    sp.type = "direct";
    return PeriodicHomogenization<2>(
      MPI_COMM_WORLD, Point<2>(1, 1), {{n, n}}, sp, degree);
  }
} // namespace

int
main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  std::vector<Row>                 rows;
  for (const unsigned int degree : {1u, 2u})
    {
      for (unsigned int n = 8; n <= (degree == 1 ? 512u : 256u); n *= 2)
        {
          auto cell = grid(n, degree);
          rows.push_back({degree,
                          "uniform",
                          double(cell.n_unknowns()),
                          to_voigt(cell.homogenize(holed).C)[0][0]});
        }
      auto cell = grid(8, degree);
      for (unsigned int k = 0; k <= (degree == 1 ? 18u : 16u); ++k)
        {
          if (k > 0)
            cell.refine(holed, 0.2);
          rows.push_back({degree,
                          "adaptive",
                          double(cell.n_unknowns()),
                          to_voigt(cell.homogenize(holed).C)[0][0]});
        }
    }
  const std::size_t n  = rows.size() - 1;
  const double      d1 = rows[n - 1].c11 - rows[n].c11,
               d2      = rows[n - 2].c11 - rows[n - 1].c11;
  const double limit   = rows[n].c11 - d1 * (d1 / d2) / (1 - d1 / d2);
  std::cout << "cell,degree,strategy,unknowns,c11,relative_error\n"
            << std::setprecision(10);
  for (const auto &r : rows)
    std::cout << "rectangular hole," << r.degree << ',' << r.strategy << ','
              << r.unknowns << ',' << r.c11 << ',' << r.c11 / limit - 1 << '\n';
  std::cout << "rectangular hole,2,reference (adaptive Q2 limit),," << limit
            << ",0\n";
}
