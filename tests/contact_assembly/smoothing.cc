// The smoothing functions of penalty contact (thesis eqs. 2.8, 2.11, 2.20):
// values at the branch points, C^1 continuity, and derivatives (h_eta',
// H_eta' = h_eta, N_eta' = f y, g' of the alignment term) against central
// differences, with the Sacado derivatives the contact form uses.

#include <forma/contact/smoothing.h>

#include "../tests.h"
#include <Sacado.hpp>

using namespace forma::contact;
using AD = Sacado::Fad::DFad<double>;

double
ad_derivative(const std::function<AD(const AD &)> &f, const double x)
{
  return f(AD(1, 0, x)).dx(0);
}

int
main()
{
  initlog();
  const double eta = 0.1, h = 1e-6;
  double       worst = 0;

  // h_eta: 0, eta/4 and eta at y = -eta, 0, eta; h_eta' and H_eta' = h_eta.
  dealii::deallog << "h_eta(-eta, 0, eta) = " << h_eta(-eta, eta) << ' '
                  << h_eta(0., eta) << ' ' << h_eta(eta, eta) << std::endl;
  for (const double y : {-0.15, -0.05, 0.02, 0.08, 0.3})
    {
      const double fd = (h_eta(y + h, eta) - h_eta(y - h, eta)) / (2 * h);
      const double Fd =
        (h_eta_integral(y + h, eta) - h_eta_integral(y - h, eta)) / (2 * h);
      const double ad =
        ad_derivative([&](const AD &x) -> AD { return h_eta(x, eta); }, y);
      worst = std::max({worst,
                        std::abs(fd - h_eta_derivative(y, eta)),
                        std::abs(ad - h_eta_derivative(y, eta)),
                        std::abs(Fd - h_eta(y, eta))});
    }
  // Continuity of H_eta and h_eta' across +-eta.
  for (const double y : {-eta, eta})
    worst = std::max({worst,
                      std::abs(h_eta_integral(y + 1e-12, eta) -
                               h_eta_integral(y - 1e-12, eta)),
                      std::abs(h_eta_derivative(y + 1e-12, eta) -
                               h_eta_derivative(y - 1e-12, eta))});
  dealii::deallog << "h_eta, H_eta: derivatives within "
                  << (worst < 1e-8 ? "1e-8" : "?") << std::endl;

  // N_eta: N_eta(|y|) has the gradient f(|y|^2) y, C^1 across |y| = eta.
  worst = 0;
  for (const double r : {0.01, 0.05, 0.099, 0.101, 0.4})
    {
      const double fd =
        (smoothed_norm(r + h, eta) - smoothed_norm(r - h, eta)) / (2 * h);
      const double f  = smoothed_norm_factor(r * r, eta);
      const double ad = ad_derivative(
        [&](const AD &x) -> AD {
          return smoothed_norm_factor(AD(x * x), eta) * x;
        },
        r);
      const double fd_factor =
        (smoothed_norm_factor((r + h) * (r + h), eta) * (r + h) -
         smoothed_norm_factor((r - h) * (r - h), eta) * (r - h)) /
        (2 * h);
      worst = std::max({worst, std::abs(fd - f * r), std::abs(ad - fd_factor)});
    }
  dealii::deallog << "N_eta(0) = " << smoothed_norm(0., eta)
                  << ", N_eta(eta) = " << smoothed_norm(eta, eta)
                  << ", N_eta' = f y within " << (worst < 1e-8 ? "1e-8" : "?")
                  << std::endl;

  // Alignment g (eq. 2.20): 1 at 0, 0 at +-epsilon, slope -beta beyond.
  const double epsilon = 0.2, beta = 0.5;
  dealii::deallog << "g(0, +-epsilon) = " << alignment_g(0., epsilon, beta)
                  << ' ' << alignment_g(-epsilon, epsilon, beta) << ' '
                  << alignment_g(epsilon, epsilon, beta) << std::endl;
  worst = 0;
  for (const double z : {-0.2, -0.1, 0., 0.1, 0.2})
    {
      const auto g = [&](const AD &x) -> AD {
        return AD(alignment_g(x, epsilon, beta));
      };
      const double left  = ad_derivative(g, z - 1e-12);
      const double right = ad_derivative(g, z + 1e-12);
      worst              = std::max(worst, std::abs(left - right));
    }
  dealii::deallog
    << "g is C^1 at 0 and +-epsilon (one-sided derivatives within "
    << (worst < 1e-8 ? "1e-8" : "?") << "), g'(0.5) = "
    << (alignment_g(0.5 + h, epsilon, beta) -
        alignment_g(0.5 - h, epsilon, beta)) /
         (2 * h)
    << std::endl;
}
