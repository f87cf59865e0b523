// TensorSpline, the material map's building block (thesis ch. 4.6.2-4.6.3):
//  - a fit to samples of a cubic polynomial in 3 variables reproduces it
//    (cubic B-splines span cubics, and the second-difference penalty
//    vanishes on them up to the boundary rows) to 1e-6;
//  - the fit of a smooth function improves as the control net refines
//    (until the samples, 9 per direction, limit it);
//  - control points no sample reaches are filled smoothly (the penalty);
//  - JSON round trip;
//  - a logarithmic direction (the map's E/E_b over 0.01-0.3): a cubic in
//    log x is reproduced, where the same control points uniform in x miss
//    it by far at the small end; it survives the JSON round trip, and a
//    direction with a bound <= 0 is refused.

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

  // y = cubic in log E (E on a geometric grid 0.01 ... 0.3) plus nu.
  {
    const auto f = [](const std::vector<double> &p) {
      const double l = std::log(p[0]);
      return 0.2 + 0.3 * l + 0.05 * l * l * l / 9 + p[1];
    };
    std::vector<std::vector<double>> xl;
    std::vector<double>              y;
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; j <= 4; ++j)
        {
          xl.push_back({0.01 * std::pow(30., i / 10.), j / 4., 0});
          y.push_back(f(xl.back()));
        }
    const auto worst = [&](const TensorSpline &s) {
      double e = 0;
      for (int i = 0; i <= 40; ++i)
        {
          const std::vector<double> p = {0.01 * std::pow(30., i / 40.), 0.3, 0};
          e = std::max(e, std::abs(s.value(p) - f(p)));
        }
      return e;
    };
    TensorSpline log_axis({0.01, 0, 0},
                          {0.3, 1, 1},
                          {6, 4, 4},
                          {true, false, false});
    TensorSpline uniform({0.01, 0, 0}, {0.3, 1, 1}, {6, 4, 4});
    log_axis.fit(xl, y, 1e-9);
    uniform.fit(xl, y, 1e-9);
    const TensorSpline read = TensorSpline::from_json(log_axis.to_json());
    dealii::deallog << "log axis: cubic in log E reproduced (< 1e-6): "
                    << (worst(log_axis) < 1e-6)
                    << ", uniform in E misses it by > 0.01: "
                    << (worst(uniform) > 0.01) << ", JSON round trip: "
                    << (read.is_logarithmic(0) && !read.is_logarithmic(1) &&
                        read.value({0.017, 0.3, 0}) ==
                          log_axis.value({0.017, 0.3, 0}))
                    << std::endl;
    try
      {
        TensorSpline({0, 0, 0}, {0.3, 1, 1}, {6, 4, 4}, {true, false, false});
        dealii::deallog << "log axis from 0: NOT refused" << std::endl;
      }
    catch (const std::exception &e)
      {
        dealii::deallog << "log axis from 0 refused" << std::endl;
      }
  }
}
