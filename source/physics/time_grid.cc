#include <deal.II/base/exceptions.h>

#include <forma/physics/time_grid.h>

#include <string>

namespace forma
{
  TimeGrid
  TimeGrid::uniform(const double end_time, const unsigned int n)
  {
    TimeGrid     g;
    const double dt = end_time / n;
    g.uniform_step  = dt;
    g.times.resize(n + 1);
    for (unsigned int i = 0; i <= n; ++i)
      g.times[i] = i * dt; // as the fixed-step loop has always computed it
    return g;
  }



  TimeGrid
  TimeGrid::variable()
  {
    TimeGrid g;
    g.times         = {0.};
    g.uniform_steps = false;
    return g;
  }



  void
  TimeGrid::push(const double t)
  {
    AssertThrow(!times.empty() && t > times.back(),
                dealii::ExcMessage("time levels must increase"));
    times.push_back(t);
  }



  double
  TimeGrid::step(const unsigned int i) const
  {
    if (i == 0 || i >= times.size())
      return 0.;
    // Uniform: the one step size, bit for bit as before the grid existed.
    if (uniform_steps)
      return uniform_step;
    return times[i] - times[i - 1];
  }



  BDFCoefficients
  TimeGrid::bdf(const unsigned int i, const unsigned int order) const
  {
    if (uniform_steps)
      return bdf_coefficients_at_step(order, i);
    AssertThrow(order <= 2,
                dealii::ExcMessage("variable time steps use BDF1 or BDF2 (got "
                                   "BDF order " +
                                   std::to_string(order) + ")."));
    if (order == 1 || i == 1)
      return bdf_coefficients(1);
    const double w = step(i) / step(i - 1);
    return {{-(1 + w) * (1 + w) / (1 + 2 * w), w * w / (1 + 2 * w)},
            (1 + w) / (1 + 2 * w)};
  }



  double
  TimeGrid::trapezoid_weight(const unsigned int i) const
  {
    return 0.5 * (step(i) + step(i + 1));
  }
} // namespace forma
