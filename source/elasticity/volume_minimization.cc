// The objective of the volume stage (see volume_minimization.h).

#include "volume_minimization.h"

#include <deal.II/base/exceptions.h>
#include <deal.II/base/utilities.h>

#include <forma/base/records.h>

#include <iomanip>
#include <set>
#include <sstream>
#include <vector>

namespace forma
{
  namespace
  {
    const std::string entry = "Optimization/Volume minimization iterations";

    // Exactly (17 digits): the stage's bound is the stress it starts at.
    std::string
    exact(const double x)
    {
      std::ostringstream s;
      s << std::setprecision(17) << x;
      return s.str();
    }

    KeyValueRecord
    parse_term(const std::string &text)
    {
      const auto     colon = text.find(':');
      KeyValueRecord r;
      r.name = dealii::Utilities::trim(text.substr(0, colon));
      r.keys =
        parse_key_values(colon == std::string::npos ? "" :
                                                      text.substr(colon + 1),
                         "Objective/Terms");
      r.where = "Objective/Terms, term '" + r.name + "'";
      return r;
    }

    // `r` with its weights (and final weights) times `scale`.
    std::string
    scaled_term(const KeyValueRecord &r, const double scale)
    {
      auto keys      = r.keys;
      keys["weight"] = scale * r.key("weight", 1.);
      if (keys.count("final weight"))
        keys["final weight"] *= scale;
      std::string text = r.name + " :";
      for (const auto &[key, value] : keys)
        text += (text.back() == ':' ? " " : ", ") + key + "=" + exact(value);
      return text;
    }

    bool
    is_stress(const std::string &name)
    {
      return name == "stress" || name == "von mises";
    }
  } // namespace



  KeyValueRecord
  stress_term_of(const std::string &terms)
  {
    std::vector<KeyValueRecord> found;
    for (const auto &text : split_top_level(terms, ';'))
      if (!dealii::Utilities::trim(text).empty())
        if (auto r = parse_term(text); is_stress(r.name))
          found.push_back(r);
    AssertThrow(found.size() == 1,
                dealii::ExcMessage(
                  entry +
                  ": the stage holds the stress of one 'stress' or "
                  "'von mises' term of Objective/Terms; there are " +
                  std::to_string(found.size()) + "."));
    return found[0];
  }



  std::string
  volume_minimization_terms(const std::string &terms,
                            const double       J0,
                            const double       S1,
                            const double       V1,
                            const double       slack,
                            const double       w,
                            const double       scale)
  {
    AssertThrow(J0 > 0 && S1 > 0 && V1 > 0,
                dealii::ExcMessage(
                  entry +
                  ": the stress norm, the volume and the objective "
                  "must be positive when the stage starts (got S1 = " +
                  exact(S1) + ", V1 = " + exact(V1) + ", J0 = " + exact(J0) +
                  ")."));
    const auto        stress = stress_term_of(terms);
    const std::string material =
      stress.keys.count("material") ?
        ", material=" + exact(stress.keys.at("material")) :
        "";
    std::string result = "volume : weight=" + exact(scale * J0 / V1) + material;
    result += " ; " + stress.name +
              " norm bound : p=" + exact(stress.key("p", 2.)) +
              ", bound=" + exact((1 + slack) * S1) +
              ", weight=" + exact(scale * J0 * w / (S1 * S1)) + material;
    const std::set<std::string> replaced = {
      "stress", "von mises", "volume", "volume bound", "volume target"};
    for (const auto &text : split_top_level(terms, ';'))
      if (!dealii::Utilities::trim(text).empty())
        if (const auto r = parse_term(text); !replaced.count(r.name))
          result += " ; " + scaled_term(r, scale);
    return result;
  }
} // namespace forma
