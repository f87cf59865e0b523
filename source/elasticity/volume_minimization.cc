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
  volume_minimization_terms(const std::string &terms, const VolumeStage &v)
  {
    AssertThrow(v.J0 > 0 && v.V1 > 0 && v.norm > 0 && v.peak > 0,
                dealii::ExcMessage(
                  entry +
                  ": the objective, the volume and the stress must be "
                  "positive when the stage starts (got J0 = " +
                  exact(v.J0) + ", V1 = " + exact(v.V1) + ", S1 = " +
                  exact(v.norm) + ", s1 = " + exact(v.peak) + ")."));
    const auto        stress = stress_term_of(terms);
    const std::string material =
      stress.keys.count("material") ?
        ", material=" + exact(stress.keys.at("material")) :
        "";
    const double k = v.scale * v.J0;
    std::string  result =
      "volume : weight=" + exact(k / v.V1) + material + " ; " + stress.name;
    if (v.hold_peak)
      result += " bound : bound=" + exact((1 + v.slack) * v.peak) +
                ", weight=" + exact(k * v.weight / (v.peak * v.peak * v.V1));
    else
      result += " norm bound : p=" + exact(stress.key("p", 2.)) +
                ", bound=" + exact((1 + v.slack) * v.norm) +
                ", weight=" + exact(k * v.weight / (v.norm * v.norm));
    result += material;
    const std::set<std::string> replaced = {
      "stress", "von mises", "volume", "volume bound", "volume target"};
    for (const auto &text : split_top_level(terms, ';'))
      if (!dealii::Utilities::trim(text).empty())
        if (const auto r = parse_term(text); !replaced.count(r.name))
          result += " ; " + scaled_term(r, v.scale);
    return result;
  }
} // namespace forma
