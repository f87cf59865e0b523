// doc/parameters/<app>.md is what `<app> --parameter-reference` writes
// from the code today, for all four applications: a parameter added,
// renamed or re-documented without rerunning
// contrib/doc/update_parameter_reference.sh fails here.

#include "../tests.h"

#include <filesystem>

int
main()
{
  initlog();
  const std::string bin = std::filesystem::path(FORMA_APP).parent_path();
  for (const std::string app : {"forma-contact-assembly",
                                "forma-transient-ipc",
                                "forma-rhombic",
                                "forma-laminate"})
    {
      const int status =
        std::system((bin + "/" + app + " --parameter-reference > " + app +
                     ".md 2> " + app + ".stderr")
                      .c_str());
      const std::string now       = read_file(app + ".md");
      const std::string committed = read_file(std::string(FORMA_SOURCE_DIR) +
                                              "/doc/parameters/" + app + ".md");
      dealii::deallog << "doc/parameters/" << app << ".md: exit code "
                      << WEXITSTATUS(status) << ", current: "
                      << (!now.empty() && now == committed ? "yes" : "no")
                      << std::endl;
    }
}
