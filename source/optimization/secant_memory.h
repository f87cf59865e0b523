#ifndef forma_optimization_secant_memory_h
#define forma_optimization_secant_memory_h

#include <ROL_Secant.hpp>
#include <nlohmann/json.hpp>

namespace forma
{
  namespace internal
  {
    /// The L-BFGS memory of a run (ROL's secant pairs s, y and s.y, in the
    /// optimizer's scaled variables z) as the checkpoint keeps it, so that a
    /// resumed run takes the steps the uninterrupted one would have.
    nlohmann::json
    secant_to_json(const ROL::Secant<double> &secant);

    /// Put a memory written by secant_to_json() into `secant`, a fresh one
    /// of the run's storage (the newest pairs are kept if the memory was
    /// larger). Throws if the pairs do not have `n` entries.
    void
    secant_from_json(const nlohmann::json &memory,
                     const unsigned int    n,
                     ROL::Secant<double>  &secant);
  } // namespace internal
} // namespace forma

#endif
