#include <deal.II/base/exceptions.h>

#include <forma/base/replace_file.h>

#include <filesystem>
#include <fstream>

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



  void
  replace_file_text(const std::string &file, const std::string &text)
  {
    replace_file(file, [&](const std::string &tmp) {
      std::ofstream out(tmp, std::ios::binary);
      out << text;
      // A full disk shows when the buffer goes out, at the latest here.
      out.close();
      AssertThrow(!out.fail(),
                  dealii::ExcMessage("cannot write '" + file +
                                     "' (is the disk full, or the directory "
                                     "not writable?)"));
    });
  }
} // namespace forma
