#include <forma/base/replace_file.h>

#include <filesystem>

namespace forma
{
  void
  replace_file(const std::string                              &file,
               const std::function<void(const std::string &)> &write)
  {
    const std::string tmp = file + ".tmp";
    write(tmp);
    std::filesystem::rename(tmp, file);
  }
} // namespace forma
