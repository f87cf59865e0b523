#ifndef forma_base_safe_text_h
#define forma_base_safe_text_h

#include <cstddef>
#include <string>

namespace forma
{
  /**
   * `text` made safe to print and to store in JSON: valid UTF-8 and the
   * line breaks and tabs stay, every other control byte and every byte
   * that is not part of a valid UTF-8 sequence becomes `\xNN`; beyond
   * `max_length` bytes the text is cut at a character boundary and says
   * how much was left off. Error messages quote user files (a mesh's bytes,
   * a parameter value) through this, so the error path cannot fail on them.
   */
  std::string
  safe_text(const std::string &text, const std::size_t max_length = 600);
} // namespace forma

#endif
