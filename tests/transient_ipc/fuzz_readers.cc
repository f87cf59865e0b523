// A bounded campaign of contrib/fuzz/fuzz_readers.py: mutated Gmsh meshes,
// OBJ obstacles, .prm files, PGM and PNG structure images, a rhombic
// material map and an optimization checkpoint read by Resume (bit flips,
// junk and binary bytes, truncation, special numbers, line edits, bad
// encodings; PNG chunks with valid checksums) for all four apps' readers.
// Every case must succeed or fail cleanly: exit code 1, one `error:` line,
// a valid failed-run/summary.json, no signal, no hang. (A mesh of binary
// junk used to abort with exit code 134.) Seeded, so the cases are the same
// on every run; the long campaign's counts are in the issue notes.

#include "../tests.h"

#include <filesystem>
#include <regex>

int
main()
{
  initlog();
  const std::string bin     = std::filesystem::path(FORMA_APP).parent_path();
  const std::string command = std::string("python3 ") + FORMA_SOURCE_DIR +
                              "/contrib/fuzz/fuzz_readers.py " + bin +
                              " --cases 12 --seed 1 --timeout 120"
                              " > fuzz.txt 2>&1";
  const int status = std::system(command.c_str());
  dealii::deallog << "campaign exit code " << WEXITSTATUS(status) << std::endl;
  std::istringstream lines(read_file("fuzz.txt"));
  const std::regex   summary("^(.*): (\\d+) cases, .* (\\d+) findings$");
  for (std::string line; std::getline(lines, line);)
    {
      std::smatch m;
      if (std::regex_match(line, m, summary))
        dealii::deallog << m[1] << ": " << m[2] << " cases, " << m[3]
                        << " findings" << std::endl;
      else
        dealii::deallog << "finding: " << line.substr(0, 160) << std::endl;
    }
}
