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
} // namespace forma

#endif
