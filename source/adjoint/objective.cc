// The objective J = sum_t weight_t Phi_t(I_t) of thesis eq. 3.10: its
// parameters and its terms, made by name from the registry (the terms live
// in objective_terms/).

#include <deal.II/base/function_parser.h>
#include <deal.II/base/utilities.h>

#include <forma/adjoint/objective.h>
#include <forma/base/records.h>

#include <cmath>

namespace forma
{
  using namespace dealii;

  template <int dim>
  ObjectiveTerm<dim>::ObjectiveTerm(const std::string &name,
                                    const double       weight)
    : name(name)
    , weight(weight)
    , first_weight(weight)
    , last_weight(weight)
  {}



  void
  ObjectiveParameters::declare(ParameterHandler &prm)
  {
    prm.enter_subsection("Objective");
    {
      prm.declare_entry(
        "Terms",
        "",
        Patterns::Anything(),
        "Records 'name : key=value, ...' separated by ';', all with an "
        "optional weight (default 1) and 'final weight' (with "
        "Optimization/Outer iterations: the weight goes linearly from "
        "'weight' in the first outer iteration to 'final weight' in the last, "
        "thesis Table 2.2's 'a/b'). The stress, compliance, volume, center "
        "of mass, height and contact force terms take 'material=id' to "
        "integrate over one part only (e.g. the printed connectors of an "
        "assembly, the object a throw pushes). Terms (name: keys and "
        "meaning; equations of the thesis):\n" +
          ObjectiveTermRegistry<2>::instance().documentation());
      prm.declare_entry("Time weighting",
                        "integral",
                        Patterns::Selection("integral|final"),
                        "Transient runs: integrate the terms over time "
                        "(trapezoidal rule, eq. 3.14) or take the final step.");
      prm.declare_entry(
        "Target",
        "",
        Patterns::Anything(),
        "Target deformed position of the material point (X, Y[, Z]) of the "
        "mesh as read, expressions in x, y[, z], t. Empty: the deformed "
        "positions of a reference run (the mesh without Design/Shape "
        "perturbation, with Reference bodies).");
      prm.declare_entry(
        "Target noise",
        "0",
        Patterns::Double(0),
        "Standard deviation (a length) of Gaussian noise added to every "
        "displacement value of the reference run's trajectory, the same for "
        "every run and rank count: a synthetic noisy recording for recovery "
        "studies. 0: exact targets.");
      prm.declare_entry(
        "Reference bodies",
        "",
        Patterns::Anything(),
        "Material records (as Material/Bodies) of the reference run; empty: "
        "Material/Bodies. Material recovery starts from Material/Bodies and "
        "seeks these.");
    }
    prm.leave_subsection();
  }



  void
  ObjectiveParameters::parse(ParameterHandler &prm)
  {
    prm.enter_subsection("Objective");
    terms            = prm.get("Terms");
    time_weighting   = prm.get("Time weighting");
    target           = prm.get("Target");
    reference_bodies = prm.get("Reference bodies");
    target_noise     = prm.get_double("Target noise");
    prm.leave_subsection();
  }



  template <int dim>
  Objective<dim>::Objective(const Parameters &parameters,
                            const bool        state_terms_only)
    : parameters(parameters)
  {
    const std::string                    entry = "Objective/Terms";
    std::shared_ptr<FunctionParser<dim>> target;
    if (!parameters.target.empty())
      target = make_function<dim>(split_top_level(parameters.target, ','),
                                  std::vector<bool>(dim, true),
                                  {},
                                  "Objective/Target");
    const auto &registry = ObjectiveTermRegistry<dim>::instance();
    for (const auto &text : split_top_level(parameters.terms, ';'))
      {
        if (Utilities::trim(text).empty())
          continue;
        const auto      colon = text.find(':');
        TermRecord<dim> r;
        r.name = Utilities::trim(text.substr(0, colon));
        r.keys = parse_key_values(
          colon == std::string::npos ? "" : text.substr(colon + 1), entry);
        r.where  = entry + ", term '" + r.name + "'";
        r.weight = r.key("weight", 1.);
        r.target = target;
        AssertThrow(registry.has(r.name),
                    ExcMessage(entry + ": unknown term '" + r.name +
                               "' (see --print-parameters for the list)."));
        auto t = registry.get(r.name, entry).create(r);
        // `material=id` restricts a term to one part, unless the term reads
        // the key itself.
        if (r.keys.count("material") && !r.read.count("material"))
          {
            const double m = r.keys.at("material");
            AssertThrow(m >= 0 && m < 255 && m == std::floor(m),
                        ExcMessage(r.where + ": 'material' must be a material "
                                             "id (an integer >= 0)."));
            AssertThrow(t->restrictable(),
                        ExcMessage(r.where + ": 'material' is not available "
                                             "for this term."));
            t->restrict_to_material(static_cast<types::material_id>(m));
          }
        // `final weight`: the end of Algorithm 1's schedule (ramp_weight()).
        t->last_weight = r.key("final weight", r.weight);
        // A misspelt key must not pass silently as its default.
        for (const auto &[key, value] : r.keys)
          AssertThrow(r.read.count(key) || key == "material",
                      ExcMessage(r.where + ": unknown key '" + key +
                                 "' (see --print-parameters for the term's "
                                 "keys)."));
        if (!state_terms_only || t->depends_on_state())
          term_list.push_back(std::move(t));
      }
    AssertThrow(!term_list.empty() || state_terms_only,
                ExcMessage(entry + " is empty: give at least one term."));
  }



  template <int dim>
  double
  Objective<dim>::step_weight(const unsigned int i, const TimeGrid &grid) const
  {
    if (parameters.time_weighting == "final")
      return i == grid.n_steps() ? 1. : 0.;
    return grid.trapezoid_weight(i);
  }



  template <int dim>
  bool
  Objective<dim>::needs_reference_run() const
  {
    for (const auto &t : term_list)
      if (t->needs_reference_run())
        return true;
    return false;
  }

  template class Registry<ObjectiveTerm<2>, const TermRecord<2> &>;
  template class Registry<ObjectiveTerm<3>, const TermRecord<3> &>;
  template class ObjectiveTerm<2>;
  template class ObjectiveTerm<3>;
  template class Objective<2>;
  template class Objective<3>;
} // namespace forma
