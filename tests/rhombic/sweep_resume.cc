// A sweep interrupted after some samples resumes from
// <Output directory>/sweep_progress.csv: the finished samples are taken
// over, the rest computed, and samples.csv equals an uninterrupted run's.

#include "../tests.h"

#include <filesystem>
#include <fstream>
#include <sstream>

const std::string prm =
  "set Output directory = results\nset Mode = sweep\n"
  "subsection Mesh\n set Element size = 0.1\n"
  " set Boundary element size = 0.05\nend\n"
  "subsection Sweep\n set p3 = 0.3, 0.6\n set p6 = 0.08, 0.16\n"
  " set Resume = true\nend\n";

int
main()
{
  initlog();
  run_app(FORMA_APP, "full", prm);
  const std::string full = read_file("results/samples.csv");
  dealii::deallog << "full run: progress file removed: "
                  << !std::filesystem::exists("results/sweep_progress.csv")
                  << std::endl;

  // An interrupted run: its progress file holds the first two samples and
  // a line cut short.
  std::istringstream lines(full);
  std::string        line, partial;
  for (unsigned int k = 0; k < 3 && std::getline(lines, line); ++k)
    partial += line + "\n";
  partial += line.substr(0, line.size() / 2) + "\n";
  std::ofstream("results/sweep_progress.csv") << partial;
  run_app(FORMA_APP, "resumed", prm);
  std::string out = read_file("resumed.stdout");
  dealii::deallog << "resumed run says: " << out.substr(0, out.find('\n'))
                  << std::endl;
  dealii::deallog << "samples.csv equal to the full run's: "
                  << (read_file("results/samples.csv") == full) << std::endl;
}
