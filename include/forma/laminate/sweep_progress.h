#ifndef forma_laminate_sweep_progress_h
#define forma_laminate_sweep_progress_h

#include <map>
#include <string>
#include <vector>

namespace forma
{
  class RunContext;

  namespace laminate
  {
    /**
     * A sweep's progress file (`<Output directory>/sweep_progress.csv`):
     * the settings the samples depend on, then one line per finished
     * structure (its index in the sweep and its values, exact to the last
     * bit), appended after every batch. A killed sweep run again with
     * `Sweep/Resume` takes those structures over and computes the rest, so
     * it gives the uninterrupted sweep's samples.
     */
    class SweepProgress
    {
    public:
      /// Start the file afresh, or with `resume` take over what an earlier
      /// run with the same `settings` (entry -> value) finished: rows of
      /// `n_values` values for structures below `n_structures` (a row the
      /// kill cut short is left out, and the file rewritten without it). A
      /// file of other settings is refused, naming the first that differs.
      /// Collective over the context's ranks.
      SweepProgress(const std::string                        &file,
                    const std::map<std::string, std::string> &settings,
                    const bool                                resume,
                    const unsigned int                        n_structures,
                    const unsigned int                        n_values,
                    RunContext                               &context);

      /// The values of structure k taken over from the file, or nullptr.
      const std::vector<double> *
      done(const unsigned int k) const;

      /// How many structures were taken over.
      unsigned int
      n_done() const;

      /// Append the rows `finished` of `table` (n_values per structure) to
      /// the file. Root only; a failed write costs the resumability only
      /// (logged).
      void
      append(const std::vector<unsigned int> &finished,
             const std::vector<double>       &table) const;

    private:
      std::string                                 file;
      unsigned int                                n_values;
      RunContext                                 &context;
      std::map<unsigned int, std::vector<double>> rows;
    };
  } // namespace laminate
} // namespace forma

#endif
