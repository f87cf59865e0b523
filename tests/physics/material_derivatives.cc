// Finite-difference checks of the constitutive derivatives every force and
// the adjoint rely on: stress = dW/d(grad u) and tangent = d stress/d(grad u)
// for linear and Neo-Hookean materials, both damping tangents, and BDF
// exactness for polynomials of the scheme's order.

#include <deal.II/base/tensor.h>

#include <forma/physics/bdf.h>
#include <forma/physics/damping.h>
#include <forma/physics/material.h>

#include "../tests.h"

using namespace dealii;

template <int dim>
Tensor<2, dim>
sample_gradient(const double scale)
{
  Tensor<2, dim> G;
  for (unsigned int i = 0; i < dim; ++i)
    for (unsigned int j = 0; j < dim; ++j)
      G[i][j] = scale * std::sin(1.3 * i + 0.7 * j + 0.4);
  return G;
}

template <int dim, typename F, typename DF>
double
fd_error(const Tensor<2, dim> &G, const F &f, const DF &df)
{
  // central differences of f along each unit direction of grad u
  const double h   = 1e-6;
  double       err = 0, ref = 0;
  for (unsigned int k = 0; k < dim; ++k)
    for (unsigned int l = 0; l < dim; ++l)
      {
        Tensor<2, dim> H;
        H[k][l]             = h;
        const auto fd       = (f(G + H) - f(G - H)) / (2 * h);
        const auto analytic = df(G, k, l);
        err                 = std::max(err, (fd - analytic).norm());
        ref                 = std::max(ref, analytic.norm());
      }
  return err / ref;
}

template <int dim>
void
check_materials()
{
  forma::MaterialProperties p = forma::MaterialProperties::from_key_values(
    {{"E", 200.}, {"nu", 0.3}},
    forma::ConstitutiveModel::neo_hookean,
    dim,
    "test");
  for (const auto model : {forma::ConstitutiveModel::linear_elastic,
                           forma::ConstitutiveModel::neo_hookean})
    {
      const forma::Material<dim> m(model, p);
      const Tensor<2, dim>       G = sample_gradient<dim>(0.2);
      // stress = dW/dG
      const double   h = 1e-6;
      Tensor<2, dim> fd;
      for (unsigned int k = 0; k < dim; ++k)
        for (unsigned int l = 0; l < dim; ++l)
          {
            Tensor<2, dim> H;
            H[k][l] = h;
            fd[k][l] =
              (m.energy_density(G + H) - m.energy_density(G - H)) / (2 * h);
          }
      const double e_stress  = (fd - m.stress(G)).norm() / m.stress(G).norm();
      const double e_tangent = fd_error<dim>(
        G,
        [&](const Tensor<2, dim> &g) { return m.stress(g); },
        [&](const Tensor<2, dim> &g, unsigned int k, unsigned int l) {
          const auto     A = m.tangent(g);
          Tensor<2, dim> col;
          for (unsigned int i = 0; i < dim; ++i)
            for (unsigned int j = 0; j < dim; ++j)
              col[i][j] = A[i][j][k][l];
          return col;
        });
      deallog << dim << "D "
              << (model == forma::ConstitutiveModel::linear_elastic ?
                    "linear" :
                    "neo-hookean")
              << ": stress = dW/dF to 1e-7: "
              << (e_stress < 1e-7 ? "yes" : "no")
              << ", tangent = dP/dF to 1e-7: "
              << (e_tangent < 1e-7 ? "yes" : "no") << std::endl;
    }

  const forma::Damping<dim> damping(0.7, 0.4);
  const Tensor<2, dim>      G0 = sample_gradient<dim>(0.1);
  const Tensor<2, dim>      G1 = sample_gradient<dim>(0.15) + 0.05 * G0;
  const double              dt = 0.01;
  auto column = [](const Tensor<4, dim> &A, unsigned int k, unsigned int l) {
    Tensor<2, dim> col;
    for (unsigned int i = 0; i < dim; ++i)
      for (unsigned int j = 0; j < dim; ++j)
        col[i][j] = A[i][j][k][l];
    return col;
  };
  const double e_current = fd_error<dim>(
    G1,
    [&](const Tensor<2, dim> &g) { return damping.stress(g, G0, dt); },
    [&](const Tensor<2, dim> &g, unsigned int k, unsigned int l) {
      return column(damping.tangent(g, G0, dt), k, l);
    });
  const double e_old = fd_error<dim>(
    G0,
    [&](const Tensor<2, dim> &g) { return damping.stress(G1, g, dt); },
    [&](const Tensor<2, dim> &g, unsigned int k, unsigned int l) {
      return column(damping.tangent_old(G1, g, dt), k, l);
    });
  deallog << dim
          << "D damping: d/du^i to 1e-7: " << (e_current < 1e-7 ? "yes" : "no")
          << ", d/du^{i-1} to 1e-7: " << (e_old < 1e-7 ? "yes" : "no")
          << std::endl;
}

void
check_bdf()
{
  // BDF-m differentiates polynomials of degree <= m exactly.
  for (unsigned int m = 1; m <= 6; ++m)
    {
      const auto   c   = forma::bdf_coefficients(m);
      const double dt  = 0.1;
      double       err = 0;
      for (unsigned int p = 0; p <= m; ++p)
        {
          const double t   = 1.0;
          double       lhs = std::pow(t, p);
          for (unsigned int j = 1; j <= m; ++j)
            lhs += c.alpha[j - 1] * std::pow(t - j * dt, p);
          const double rhs =
            c.beta * dt * (p == 0 ? 0. : p * std::pow(t, p - 1));
          err = std::max(err, std::abs(lhs - rhs));
        }
      deallog << "BDF" << m << " exact for degree <= " << m << ": "
              << (err < 1e-12 ? "yes" : "no") << std::endl;
    }
}

int
main()
{
  initlog();
  check_materials<2>();
  check_materials<3>();
  check_bdf();
}
