#ifndef forma_contact_contact_parameters_h
#define forma_contact_contact_parameters_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/types.h>

#include <map>
#include <string>

namespace forma
{
  /// Smoothed penalty parameters of one contact boundary (thesis ch. 2.3.4).
  struct ContactLaw
  {
    double alpha = 1e-4; ///< 1/alpha is the penalty (force / length^3)
    double eta   = 1e-4; ///< smoothing width of h_eta (length)
    double mu    = 0;    ///< Coulomb friction coefficient
    double eta_n = 1e-4; ///< smoothing width of N_eta (length)
  };

  /**
   * The `Contact` section: which boundaries are in contact and how.
   *   set Rigid-deformable      = 3 : alpha=1e-5, eta=1e-5
   *   set Deformable-deformable = 10 : alpha=1e-5, mu=0.3, eta_n=1e-4
   * Rigid-deformable (RD) boundaries touch a rigid obstacle that follows
   * the boundary's initial shape: u . n <= 0 (eq. 2.5). Deformable-deformable
   * (DD) boundaries are interfaces cut open by Mesh/Separate interfaces;
   * their two sides are paired face by face (eq. 2.6).
   */
  struct ContactParameters
  {
    std::string rigid_deformable;
    std::string deformable_deformable;

    std::map<dealii::types::boundary_id, ContactLaw> rigid, deformable;

    /// `Rigid gaps`: per RD boundary, the obstacle's initial distance
    /// along the boundary's outer normal as an expression in x, y (, z);
    /// boundaries not named touch the obstacle everywhere (gap 0).
    std::string                                       rigid_gaps_text;
    std::map<dealii::types::boundary_id, std::string> rigid_gaps;

    /// Face quadrature: `gauss` (degree + 1 points per direction) or
    /// `adaptive` (thesis ch. 2.9.4, see contact::adaptive_quadrature()).
    std::string  quadrature     = "gauss";
    unsigned int adaptive_depth = 5;
    unsigned int gauss_points   = 4;
    unsigned int samples        = 6;

    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(dealii::ParameterHandler &prm);

    bool
    empty() const
    {
      return rigid.empty() && deformable.empty();
    }
    bool
    has_friction() const;
  };

} // namespace forma

#endif
