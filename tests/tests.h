// Shared helpers for forma's unit tests (deal.II harness): a test writes its
// results to the file "output" through deallog, which numdiff compares with
// the stored <name>.output.
#ifndef forma_tests_h
#define forma_tests_h

#include <deal.II/base/logstream.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iomanip>
#include <sstream>
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

/// The whole content of a file ("" if it does not exist).
inline std::string
read_file(const std::string &file)
{
  std::ifstream      in(file);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Run `app` on `prm` (written to name.prm); stdout and stderr go to
/// name.stdout and name.stderr. Returns the exit code.
inline int
run_app(const std::string &app, const std::string &name, const std::string &prm)
{
  std::ofstream(name + ".prm") << prm;
  const int status = std::system(
    (app + " " + name + ".prm > " + name + ".stdout 2> " + name + ".stderr")
      .c_str());
  return WEXITSTATUS(status);
}

/// Run a bad input and log whether it failed cleanly: a non-zero exit code,
/// results/summary.json still equal to `good`, and the error message.
inline void
expect_failure(const std::string &app,
               const std::string &name,
               const std::string &prm,
               const std::string &good)
{
  const int code = run_app(app, name, prm);
  dealii::deallog << name
                  << ": exit code non-zero: " << (code != 0 ? "yes" : "no")
                  << ", earlier results untouched: "
                  << (read_file("results/summary.json") == good ? "yes" : "no")
                  << std::endl;
  std::string message = read_file(name + ".stderr");
  while (!message.empty() && message.back() == '\n')
    message.pop_back();
  dealii::deallog << "  message: " << message << std::endl;
}

#if defined(FORMA_APP) && defined(FORMA_SOURCE_DIR)
/// Run the shipped example parameter_files/<directory>/<name>.prm as a user
/// would (output into ./<name>, `extra` further arguments), log its exit
/// code and status, and return its summary.json.
inline nlohmann::json
run_example(const std::string &directory,
            const std::string &name,
            const std::string &extra = "")
{
  const std::string prm = std::string(FORMA_SOURCE_DIR) + "/parameter_files/" +
                          directory + "/" + name + ".prm";
  const int      status = std::system((std::string(FORMA_APP) + " " + prm +
                                  " --set 'Output directory=" + name + "'" +
                                  extra + " > " + name + ".stdout 2>&1")
                                   .c_str());
  nlohmann::json s;
  std::ifstream(name + "/summary.json") >> s;
  dealii::deallog << name << ": exit code " << WEXITSTATUS(status)
                  << ", status " << s["status"].get<std::string>() << std::endl;
  return s;
}
#endif

/// Log a named yes/no finding.
inline void
check(const std::string &what, const bool ok)
{
  dealii::deallog << "  " << what << ": " << (ok ? "yes" : "NO") << std::endl;
}

/// Run f, which must throw an exception whose message contains `needle`:
/// logs "<what>: refused", or what happened instead.
inline void
expect_refusal(const std::string           &what,
               const std::function<void()> &f,
               const std::string           &needle)
{
  try
    {
      f();
      dealii::deallog << what << ": no error: WRONG" << std::endl;
    }
  catch (const std::exception &e)
    {
      const std::string message = e.what();
      dealii::deallog << what << ": "
                      << (message.find(needle) != std::string::npos ?
                            "refused" :
                            message)
                      << std::endl;
    }
}

#ifdef FORMA_APP
/// expect_failure() for the application under test (FORMA_APP).
inline void
expect_failure(const std::string &name,
               const std::string &prm,
               const std::string &good)
{
  expect_failure(FORMA_APP, name, prm, good);
}
#endif

/// A Taylor test's rate as a verdict ("in [1.8, 2.3]" or the value):
/// printed values could round either way.
inline std::string
rate_verdict(const double rate)
{
  std::ostringstream v;
  if (rate >= 1.8 && rate <= 2.3)
    v << "in [1.8, 2.3]";
  else
    v << "= " << rate << " (expected about 2)";
  return v.str();
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
