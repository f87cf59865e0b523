// TensorSpline, the material map's building block (thesis ch. 4.6.2-4.6.3):
//  - a fit to samples of a cubic polynomial in 3 variables reproduces it
//    (cubic B-splines span cubics, and the second-difference penalty
//    vanishes on them up to the boundary rows) to 1e-6;
//  - the fit of a smooth function improves as the control net refines
//    (until the samples, 9 per direction, limit it);
//  - control points no sample reaches are filled smoothly (the penalty);
//  - JSON round trip.

#include <forma/rhombic/material_map.h>

#include "../tests.h"

#include <cmath>

using namespace forma::rhombic;

int
main()
{
  initlog();
  const auto cubic = [](const std::vector<double> &x) {
    return 0.3 + x[0] - 2 * x[1] * x[1] + 0.5 * x[0] * x[1] * x[2] +
           0.1 * x[2] * x[2] * x[2];
  };
  const auto smooth = [](const std::vector<double> &x) {
    return std::sin(3 * x[0]) * std::cos(2 * x[1]) + 0.2 * x[2];
  };
  std::vector<std::vector<double>> x;
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j)
      for (int k = 0; k <= 4; ++k)
        x.push_back({i / 8., j / 8., k / 4.});
  const auto values = [&](const auto &f) {
    std::vector<double> y;
    for (const auto &p : x)
      y.push_back(f(p));
    return y;
  };
  const auto max_error = [&](const TensorSpline &s, const auto &f) {
    double e = 0;
    for (int i = 0; i <= 20; ++i)
      for (int j = 0; j <= 20; ++j)
        for (int k = 0; k <= 5; ++k)
          {
            const std::vector<double> p = {i / 20., j / 20., k / 5.};
            e = std::max(e, std::abs(s.value(p) - f(p)));
          }
    return e;
  };

  TensorSpline c({0, 0, 0}, {1, 1, 1}, {6, 6, 4});
  c.fit(x, values(cubic), 1e-9);
  dealii::deallog << "cubic reproduced: "
                  << (max_error(c, cubic) < 1e-6 ? "yes" : "NO") << std::endl;

  std::vector<double> errors;
  for (const unsigned int n : {4u, 6u, 10u})
    {
      TensorSpline s({0, 0, 0}, {1, 1, 1}, {n, n, 4});
      s.fit(x, values(smooth), 1e-6);
      errors.push_back(max_error(s, smooth));
    }
  dealii::deallog << "smooth function: error falls with the control net: "
                  << (errors[1] < 0.25 * errors[0] && errors[2] <= errors[1])
                  << ", finest < 0.01: " << (errors[2] < 0.01) << std::endl;

  // Samples only in half the box: the other half is filled, bounded.
  {
    std::vector<std::vector<double>> half;
    std::vector<double>              y;
    for (const auto &p : x)
      if (p[0] <= 0.5)
        half.push_back(p), y.push_back(smooth(p));
    TensorSpline s({0, 0, 0}, {1, 1, 1}, {8, 8, 4});
    s.fit(half, y, 1e-3);
    double worst = 0;
    for (const auto &p : x)
      worst = std::max(worst, std::abs(s.value(p)));
    dealii::deallog << "extrapolated half stays bounded (|value| < 5): "
                    << (worst < 5) << std::endl;
  }

  const TensorSpline r = TensorSpline::from_json(c.to_json());
  dealii::deallog << "JSON round trip: "
                  << (std::abs(r.value({0.3, 0.7, 0.2}) -
                               c.value({0.3, 0.7, 0.2})) == 0)
                  << std::endl;
}
