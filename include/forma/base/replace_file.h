#ifndef forma_base_replace_file_h
#define forma_base_replace_file_h

#include <functional>
#include <string>

namespace forma
{
  /**
   * Replace `file` whole: `write` writes `file`.tmp, which is then renamed
   * over it, so a kill at any moment leaves the old or the new file, never
   * half of one (progress and checkpoint files read back to resume).
   */
  void
  replace_file(const std::string                              &file,
               const std::function<void(const std::string &)> &write);

  /**
   * Replace `file` whole with `text` (see replace_file()). Throws, and
   * leaves the old file as it was, if the text cannot be written in full
   * (a full disk, an unwritable directory).
   */
  void
  replace_file_text(const std::string &file, const std::string &text);
} // namespace forma

#endif
