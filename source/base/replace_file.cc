#include <forma/base/replace_file.h>

#include <filesystem>

namespace forma
{
  void
  replace_file(const std::string                              &file,
               const std::function<void(const std::string &)> &write)
  {
    const std::string tmp = file + ".tmp";
    try
      {
        write(tmp);
      }
    catch (...)
      {
        // No half-written temporary left beside a good file.
        std::error_code ignored;
        std::filesystem::remove(tmp, ignored);
        throw;
      }
    std::filesystem::rename(tmp, file);
  }
} // namespace forma
