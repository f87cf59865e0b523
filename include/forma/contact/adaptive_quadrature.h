#ifndef forma_contact_adaptive_quadrature_h
#define forma_contact_adaptive_quadrature_h

#include <deal.II/base/point.h>
#include <deal.II/base/quadrature.h>

#include <functional>

namespace forma
{
  namespace contact
  {
    /**
     * A composite Gauss rule on a reference face that follows the kinks of
     * piecewise integrands (thesis ch. 2.9.4): the face (the segment [0, 1],
     * the triangle (0,0),(1,0),(0,1) or the square [0, 1]^2) is split into 2
     * or 4 similar pieces, recursively up to `max_depth`, while the integer
     * `regime` (the branch of h_eta, N_eta at a point) differs between the
     * `samples` x `samples` sample points of a piece (evenly spread, corners
     * included); every final piece gets a Gauss rule of `n_gauss` points per
     * direction (collapsed, Duffy, on triangles). `regime` receives all
     * sample points of a piece at once and returns one code per point.
     */
    template <int face_dim>
    dealii::Quadrature<face_dim>
    adaptive_quadrature(
      const bool simplex,
      const std::function<
        std::vector<int>(const std::vector<dealii::Point<face_dim>> &)> &regime,
      const unsigned int n_gauss,
      const unsigned int max_depth,
      const unsigned int samples);

    /// The branch code of the smoothed contact functions at a point: of
    /// h_eta(gap) (3 branches) and, where h_eta > 0 and there is friction,
    /// of N_eta(slip) (inside/outside the ball of radius eta_n).
    int
    contact_regime(const double gap,
                   const double slip,
                   const double eta,
                   const double eta_n,
                   const bool   friction);
  } // namespace contact
} // namespace forma

#endif
