#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <forma/adjoint/gradient_check.h>

#include <cmath>
#include <limits>
#include <random>

namespace forma
{
  using namespace dealii;

  void
  GradientCheckParameters::declare(ParameterHandler &prm)
  {
    prm.enter_subsection("Gradient check");
    prm.declare_entry("First step",
                      "1e-2",
                      Patterns::Double(0),
                      "epsilon of the first row of the Taylor table; the "
                      "direction is scaled per block (cell size for shape, "
                      "the value itself for materials).");
    prm.declare_entry("Steps",
                      "5",
                      Patterns::Integer(2, 30),
                      "Rows of the table; epsilon halves from row to row.");
    prm.declare_entry("Seed",
                      "1",
                      Patterns::Integer(0),
                      "Seed of the random direction.");
    prm.declare_entry("Blocks",
                      "",
                      Patterns::Anything(),
                      "Design blocks the direction perturbs (comma-"
                      "separated names of Design/Parameters); empty: all.");
    prm.leave_subsection();
  }



  void
  GradientCheckParameters::parse(ParameterHandler &prm)
  {
    prm.enter_subsection("Gradient check");
    first_step = prm.get_double("First step");
    n_steps    = prm.get_integer("Steps");
    seed       = prm.get_integer("Seed");
    blocks     = prm.get("Blocks");
    prm.leave_subsection();
  }



  nlohmann::json
  GradientCheckResult::to_json() const
  {
    auto number = [](const double x) {
      return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json();
    };
    nlohmann::json table = nlohmann::json::array();
    for (unsigned int k = 0; k < epsilons.size(); ++k)
      table.push_back({{"epsilon", epsilons[k]},
                       {"objective", values[k]},
                       {"error", errors[k]}});
    nlohmann::json r = nlohmann::json::array();
    for (const double x : rates)
      r.push_back(number(x));
    return {{"objective", value},
            {"directional_derivative", directional_derivative},
            {"table", table},
            {"rates", r},
            {"min_rate", number(min_rate)}};
  }



  std::vector<double>
  random_direction(const DesignLayout            &layout,
                   const std::vector<double>     &scale,
                   const GradientCheckParameters &parameters)
  {
    const auto selected = Utilities::split_string_list(parameters.blocks, ',');
    for (const auto &name : selected)
      AssertThrow(layout.find(name),
                  ExcMessage("Gradient check/Blocks: '" + name +
                             "' is not in Design/Parameters."));
    std::mt19937                           generator(parameters.seed);
    std::uniform_real_distribution<double> uniform(-1., 1.);
    std::vector<double>                    theta(scale.size(), 0.);
    for (const auto &b : layout.blocks)
      {
        const bool on =
          selected.empty() ||
          std::find(selected.begin(), selected.end(), b.name) != selected.end();
        for (unsigned int i = b.offset; i < b.offset + b.size; ++i)
          {
            const double r = uniform(generator); // drawn for every entry
            if (on)
              theta[i] = scale[i] * r;
          }
      }
    return theta;
  }



  GradientCheckResult
  taylor_test(
    const std::function<double(const std::vector<double> &)> &objective,
    const std::function<double(const std::vector<double> &,
                               std::vector<double> &)>       &gradient,
    const std::vector<double>                                &q,
    const std::vector<double>                                &direction,
    const GradientCheckParameters                            &parameters)
  {
    GradientCheckResult r;
    std::vector<double> dJ;
    r.value = gradient(q, dJ);
    for (unsigned int i = 0; i < q.size(); ++i)
      r.directional_derivative += dJ[i] * direction[i];

    double eps = parameters.first_step;
    for (unsigned int k = 0; k < parameters.n_steps; ++k, eps *= 0.5)
      {
        std::vector<double> qe(q);
        for (unsigned int i = 0; i < q.size(); ++i)
          qe[i] += eps * direction[i];
        const double J = objective(qe);
        r.epsilons.push_back(eps);
        r.values.push_back(J);
        r.errors.push_back(
          std::abs(J - r.value - eps * r.directional_derivative));
      }
    // Below this the error is the round-off of J, not the Taylor remainder.
    const double noise = 1e-11 * (std::abs(r.value) + 1e-300);
    r.min_rate         = std::numeric_limits<double>::quiet_NaN();
    for (unsigned int k = 0; k + 1 < r.errors.size(); ++k)
      {
        const bool   valid = r.errors[k + 1] > noise;
        const double rate  = valid ? std::log2(r.errors[k] / r.errors[k + 1]) :
                                     std::numeric_limits<double>::quiet_NaN();
        r.rates.push_back(rate);
        if (valid && !(rate >= r.min_rate))
          r.min_rate = rate;
      }
    return r;
  }
} // namespace forma
