#ifndef forma_physics_time_grid_h
#define forma_physics_time_grid_h

#include <forma/physics/bdf.h>

#include <vector>

namespace forma
{
  /**
   * The time levels t_0 = 0 < t_1 < ... < t_n of a transient run and the
   * BDF coefficients on them. A uniform grid uses the fixed-step tables
   * (orders 1-6); a grid of accepted adaptive steps uses variable-step
   * BDF1/BDF2, whose coefficients follow from the step ratio
   * w = h_i / h_{i-1}:
   *   u^i - (1+w)^2/(1+2w) u^{i-1} + w^2/(1+2w) u^{i-2}
   *     = (1+w)/(1+2w) h_i udot^i.
   * The forward run, the adjoint sweep and the objective's time quadrature
   * all read the same grid, so the adjoint is the discrete one of the
   * steps actually taken.
   */
  class TimeGrid
  {
  public:
    /// n equal steps from 0 to `end_time`.
    static TimeGrid
    uniform(const double end_time, const unsigned int n);

    /// A variable grid holding t_0 = 0 only; steps follow with push().
    static TimeGrid
    variable();

    /// Appends the accepted level t (> the last one).
    void
    push(const double t);

    /// Removes the last level (a rejected step).
    void
    pop()
    {
      if (times.size() > 1)
        times.pop_back();
    }

    bool
    empty() const
    {
      return times.empty();
    }

    unsigned int
    n_steps() const
    {
      return times.empty() ? 0 : times.size() - 1;
    }

    double
    time(const unsigned int i) const
    {
      return times[i];
    }

    /// h_i = t_i - t_{i-1} (i >= 1); 0 outside the grid.
    double
    step(const unsigned int i) const;

    /// Coefficients of step i (1-based) of a BDF-`order` run: the first
    /// order-1 steps use the lower orders. Variable grids: order <= 2.
    BDFCoefficients
    bdf(const unsigned int i, const unsigned int order) const;

    /// Trapezoidal weight of level i: (h_i + h_{i+1}) / 2.
    double
    trapezoid_weight(const unsigned int i) const;

    bool
    is_uniform() const
    {
      return uniform_steps;
    }

  private:
    std::vector<double> times;
    bool                uniform_steps = true;
    double              uniform_step  = 0; ///< uniform grids: end / n
  };
} // namespace forma

#endif
