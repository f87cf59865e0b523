#include "secant_memory.h"

#include <deal.II/base/exceptions.h>

#include <ROL_StdVector.hpp>

#include <algorithm>
#include <cmath>
#include <utility>

namespace forma
{
  namespace internal
  {
    namespace
    {
      const std::vector<double> &
      entries(const ROL::Vector<double> &v)
      {
        return *dynamic_cast<const ROL::StdVector<double> &>(v).getVector();
      }



      ROL::Ptr<ROL::Vector<double>>
      vector_of(const nlohmann::json &values, const unsigned int n)
      {
        auto v = values.get<std::vector<double>>();
        AssertThrow(v.size() == n,
                    dealii::ExcMessage(
                      "an L-BFGS pair of " + std::to_string(v.size()) +
                      " entries for a design of " + std::to_string(n)));
        AssertThrow(std::all_of(v.begin(),
                                v.end(),
                                [](const double x) {
                                  return std::isfinite(x);
                                }),
                    dealii::ExcMessage("an L-BFGS pair that is not finite"));
        return ROL::makePtr<ROL::StdVector<double>>(
          ROL::makePtr<std::vector<double>>(std::move(v)));
      }
    } // namespace



    nlohmann::json
    secant_to_json(const ROL::Secant<double> &secant)
    {
      const auto    &state = *secant.get_state();
      nlohmann::json memory;
      memory["iter"] = state.iter;
      memory["s"]    = nlohmann::json::array();
      memory["y"]    = nlohmann::json::array();
      for (int i = 0; i <= state.current; ++i)
        {
          memory["s"].push_back(entries(*state.iterDiff[i]));
          memory["y"].push_back(entries(*state.gradDiff[i]));
        }
      memory["sy"] =
        std::vector<double>(state.product.begin(),
                            state.product.begin() + (state.current + 1));
      return memory;
    }



    void
    secant_from_json(const nlohmann::json &memory,
                     const unsigned int    n,
                     ROL::Secant<double>  &secant)
    {
      const auto &s  = memory.at("s");
      const auto &y  = memory.at("y");
      const auto  sy = memory.at("sy").get<std::vector<double>>();
      AssertThrow(s.is_array() && y.size() == s.size() && sy.size() == s.size(),
                  dealii::ExcMessage("the L-BFGS pairs are incomplete"));
      // ROL keeps only pairs of positive curvature.
      for (const double p : sy)
        AssertThrow(std::isfinite(p) && p > 0,
                    dealii::ExcMessage("an L-BFGS pair of curvature " +
                                       std::to_string(p)));
      const double iter = memory.at("iter").get<double>();
      AssertThrow(iter >= 0 && iter < 1e9,
                  dealii::ExcMessage("a bad L-BFGS iteration count"));
      // ROL's non-const get_state() does not compile; the const one gives
      // the same (non-const) state.
      auto             &state = *std::as_const(secant).get_state();
      const std::size_t first =
        s.size() > static_cast<std::size_t>(state.storage) ?
          s.size() - state.storage :
          0;
      state.iterDiff.clear();
      state.gradDiff.clear();
      state.product.clear();
      for (std::size_t i = first; i < s.size(); ++i)
        {
          state.iterDiff.push_back(vector_of(s[i], n));
          state.gradDiff.push_back(vector_of(y[i], n));
          state.product.push_back(sy[i]);
        }
      state.current = static_cast<int>(state.product.size()) - 1;
      state.iter    = static_cast<int>(iter);
    }
  } // namespace internal
} // namespace forma
