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
   * BDF of each step's own order (1-5): u'(t_i) from the polynomial through
   * u^i..u^{i-q}. For q = 2 with the step ratio w = h_i / h_{i-1}:
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

    /// Appends the accepted level t (> the last one), stepped to with BDF
    /// of order at most `order`.
    void
    push(const double t, const unsigned int order = max_variable_order);

    /// Removes the last level (a rejected step).
    void
    pop()
    {
      if (times.size() > 1)
        {
          times.pop_back();
          if (!orders.empty())
            orders.pop_back();
        }
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

    /// The order step i (1-based) of a BDF-`order` run uses: at most i, and
    /// on variable grids at most the order it was pushed with.
    unsigned int
    order(const unsigned int i, const unsigned int order) const;

    /// Coefficients of step i of a BDF-`order` run (orders as order(i, .)).
    BDFCoefficients
    bdf(const unsigned int i, const unsigned int order) const
    {
      return coefficients(i, this->order(i, order));
    }

    /// Coefficients of BDF-q (q <= i) at step i on this grid, whatever order
    /// the step was taken with.
    BDFCoefficients
    coefficients(const unsigned int i, const unsigned int q) const;

    /**
     * The degree-q polynomial P through u^{i-1}, ..., u^{i-q-1} evaluated
     * at t_i, as P(t_i) = sum_j u[j-1] u^{i-j} + v0 udot^0: for i = q, where
     * u^{i-q-1} does not exist, the initial velocity takes its place
     * (Hermite data at t_0). `span` is t_i minus the oldest node, so that
     * u(t_i) - P = span prod_{j=1..q} (t_i - t_{i-j}) u^(q+1) / (q+1)!.
     * Needs 1 <= q <= i.
     */
    struct Extrapolation
    {
      std::vector<double> u;
      double              v0;
      double              span;
    };
    Extrapolation
    extrapolation(const unsigned int i, const unsigned int q) const;

    /// The number of steps taken with each order 1..`order` (index 0: BDF1)
    /// in a BDF-`order` run.
    std::vector<unsigned int>
    steps_per_order(const unsigned int order) const;

    /// Trapezoidal weight of level i: (h_i + h_{i+1}) / 2.
    double
    trapezoid_weight(const unsigned int i) const;

    bool
    is_uniform() const
    {
      return uniform_steps;
    }

    /// Variable-step BDF is zero-stable up to order 5 on smooth grids.
    static constexpr unsigned int max_variable_order = 5;

  private:
    std::vector<double>       times;
    std::vector<unsigned int> orders; ///< variable grids: each step's cap
    bool                      uniform_steps = true;
    double                    uniform_step  = 0; ///< uniform grids: end / n
  };
} // namespace forma

#endif
