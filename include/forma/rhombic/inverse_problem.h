#ifndef forma_rhombic_inverse_problem_h
#define forma_rhombic_inverse_problem_h

#include <forma/rhombic/cell_model.h>
#include <forma/rhombic/study.h>

#include <array>
#include <functional>
#include <string>
#include <vector>

namespace forma
{
  class RunContext;
  struct OptimizationParameters;

  namespace rhombic
  {
    struct InverseSolution;

    /**
     * Inverse homogenization (thesis eq. 4.4): the distance of C^H to an
     * isotropic target, relative to the target,
     *   J(p) = |C^H(p) - C*|^2 / |C*|^2 + w_v phi(p) + w_p |p - p0|^2,
     * with the volume fraction phi and the proximity to the start p0 as
     * optional regularizations; only the `free` parameters vary, within
     * the sweep ranges. C* is isotropic (E*, nu*) or the C^H of a given
     * structure on the same cell (a reachable target, for recovery).
     */
    struct InverseProblem
    {
      dealii::SymmetricTensor<4, 2> target;
      double                        target_E = 0, target_nu = 0;
      double                        volume_weight = 0, proximity_weight = 0;
      std::array<double, RhombicStructure::n_parameters> start{};
      std::vector<unsigned int>                          free;
      double                                             tolerance = 0.01;
      /// The parameters' bounds: the sweep ranges unless
      /// Inverse/Parameter bounds widens or narrows some.
      std::array<std::array<double, 2>, RhombicStructure::n_parameters> bounds =
        RhombicStructure::ranges();
      /// Target = structure: the parameters whose C^H is the target.
      std::array<double, RhombicStructure::n_parameters> target_structure{};

      /// The Inverse section (range-checked); the start is `structure`.
      static InverseProblem
      read(dealii::ParameterHandler &prm,
           const Setup              &setup,
           const RhombicStructure   &structure,
           const MPI_Comm            comm);

      /// s with its free parameters set to z.
      RhombicStructure
      with(const RhombicStructure &s, const std::vector<double> &z) const;

      /// The free parameters of s.
      std::vector<double>
      free_values(const RhombicStructure &s) const;

      /// |C^H - C*| / |C*|
      double
      misfit(const Sample &r) const;

      /// J of a cell model's design; with `gradient` also dJ/dz.
      double
      objective(const CellModel &model, std::vector<double> *gradient) const;

      /**
       * Minimize J from `start` (its angle and blending are kept) with
       * bound-constrained L-BFGS (ROL, optimize()), remeshing every design,
       * on `comm`. `accepted` sees every accepted design.
       */
      InverseSolution
      solve(const RhombicStructure       &start,
            const Setup                  &setup,
            const MPI_Comm                comm,
            const OptimizationParameters &parameters,
            RunContext                   &context,
            const std::function<void(unsigned int, const CellModel &, double)>
              &accepted = {}) const;
    };

    /// The optimizer settings of pointwise inverse homogenization
    /// (Inverse/Max iterations; stops at the tolerance or on stagnation).
    OptimizationParameters
    inverse_optimization_parameters(dealii::ParameterHandler &prm,
                                    const double              tolerance);

    struct InverseSolution
    {
      RhombicStructure    structure;
      Sample              sample;
      double              misfit     = 0;
      bool                reached    = false;
      unsigned int        iterations = 0;
      std::string         stop_reason;
      std::vector<double> history;
    };
  } // namespace rhombic
} // namespace forma

#endif
