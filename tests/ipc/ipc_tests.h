// Helpers of the IPC tests: simulators from .prm text with the IPC section.
#ifndef forma_tests_ipc_h
#define forma_tests_ipc_h

#include <forma/elasticity/simulator.h>

#include "../tests.h"

template <int dim>
forma::ElasticitySimulator<dim>
make_ipc_simulator(const std::string &text)
{
  dealii::ParameterHandler prm;
  prm.declare_entry("Dimension", "2", dealii::Patterns::Integer(2, 3));
  prm.declare_entry("Output directory", "output", dealii::Patterns::Anything());
  prm.declare_entry("Mode", "simulate", dealii::Patterns::Anything());
  forma::ElasticityParameters::declare(prm);
  forma::ipc::IpcParameters::declare(prm);
  prm.parse_input_from_string("set Dimension = " + std::to_string(dim) + "\n" +
                              text);
  forma::ElasticityParameters p;
  p.parse(prm, FORMA_SOURCE_DIR "/tests/ipc", false, true);
  return forma::ElasticitySimulator<dim>(p, MPI_COMM_WORLD);
}

/// Least-squares fit x = a0 + a1 t + a2 t^2 / 2; returns a2.
inline double
fitted_acceleration(const std::vector<double> &t, const std::vector<double> &x)
{
  // Normal equations of the 3-parameter fit.
  double A[3][4] = {};
  for (unsigned int i = 0; i < t.size(); ++i)
    {
      const double b[3] = {1., t[i], 0.5 * t[i] * t[i]};
      for (unsigned int r = 0; r < 3; ++r)
        {
          for (unsigned int c = 0; c < 3; ++c)
            A[r][c] += b[r] * b[c];
          A[r][3] += b[r] * x[i];
        }
    }
  for (unsigned int k = 0; k < 3; ++k)
    for (unsigned int r = k + 1; r < 3; ++r)
      {
        const double f = A[r][k] / A[k][k];
        for (unsigned int c = k; c < 4; ++c)
          A[r][c] -= f * A[k][c];
      }
  double a[3];
  for (int k = 2; k >= 0; --k)
    {
      a[k] = A[k][3];
      for (unsigned int c = k + 1; c < 3; ++c)
        a[k] -= A[k][c] * a[c];
      a[k] /= A[k][k];
    }
  return a[2];
}

#endif
