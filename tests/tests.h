// Shared helpers for forma's unit tests (deal.II harness): a test writes its
// results to the file "output" through deallog, which numdiff compares with
// the stored <name>.output.
#ifndef forma_tests_h
#define forma_tests_h

#include <deal.II/base/logstream.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <string>
#include <vector>

std::ofstream deallogfile;

inline void
initlog(const int precision = 6)
{
  deallogfile.open("output");
  dealii::deallog.attach(deallogfile, /*print_job_id=*/false);
  dealii::deallog.depth_console(0);
  dealii::deallog << std::setprecision(precision);
  deallogfile << std::setprecision(precision);
}

/// Observed convergence rates between successive (h or n, error) pairs.
inline std::vector<double>
observed_rates(const std::vector<double> &h, const std::vector<double> &e)
{
  std::vector<double> rates;
  for (unsigned int i = 1; i < e.size(); ++i)
    rates.push_back(std::log(e[i - 1] / e[i]) / std::log(h[i - 1] / h[i]));
  return rates;
}

/// Round a number to `digits` significant digits so round-off noise below
/// that does not reach the comparison.
inline double
rounded(const double x, const int digits = 4)
{
  if (x == 0 || !std::isfinite(x))
    return x;
  const double scale =
    std::pow(10., digits - 1 - std::floor(std::log10(std::abs(x))));
  return std::round(x * scale) / scale;
}

/// Declare the simulator's parameters, then read `text` as a .prm file.
template <typename Parameters>
Parameters
parameters_from_string(const std::string &text)
{
  dealii::ParameterHandler prm;
  prm.declare_entry("Dimension", "2", dealii::Patterns::Integer(2, 3));
  prm.declare_entry("Output directory", "output", dealii::Patterns::Anything());
  prm.declare_entry("Mode", "simulate", dealii::Patterns::Anything());
  Parameters::declare(prm);
  prm.parse_input_from_string(text);
  Parameters p;
  p.parse(prm, ".");
  return p;
}

#endif
