#include <forma/base/safe_text.h>

#include <cstdio>

namespace forma
{
  namespace
  {
    /// Length of the valid UTF-8 sequence starting at text[i] (1–4), or 0
    /// if none starts there. Overlong forms and surrogates are invalid.
    std::size_t
    utf8_length(const std::string &text, const std::size_t i)
    {
      const auto byte = [&](const std::size_t k) {
        return static_cast<unsigned char>(text[k]);
      };
      const unsigned char c = byte(i);
      if (c < 0x80)
        return 1;
      std::size_t   n;
      unsigned char low = 0x80, high = 0xBF;
      if (c >= 0xC2 && c <= 0xDF)
        n = 2;
      else if (c >= 0xE0 && c <= 0xEF)
        {
          n    = 3;
          low  = (c == 0xE0) ? 0xA0 : 0x80;
          high = (c == 0xED) ? 0x9F : 0xBF;
        }
      else if (c >= 0xF0 && c <= 0xF4)
        {
          n    = 4;
          low  = (c == 0xF0) ? 0x90 : 0x80;
          high = (c == 0xF4) ? 0x8F : 0xBF;
        }
      else
        return 0;
      if (i + n > text.size() || byte(i + 1) < low || byte(i + 1) > high)
        return 0;
      for (std::size_t k = 2; k < n; ++k)
        if (byte(i + k) < 0x80 || byte(i + k) > 0xBF)
          return 0;
      return n;
    }
  } // namespace



  std::string
  safe_text(const std::string &text, const std::size_t max_length)
  {
    std::string result;
    std::size_t i = 0;
    while (i < text.size() && result.size() < max_length)
      {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        const std::size_t   n = utf8_length(text, i);
        // C1 controls (U+0080-U+009F, e.g. the terminal's CSI) too.
        const bool c1 =
          n == 2 && c == 0xC2 && static_cast<unsigned char>(text[i + 1]) < 0xA0;
        if (n == 0 || (c < 0x20 && c != '\n' && c != '\t') || c == 0x7F || c1)
          {
            char escaped[8];
            std::snprintf(escaped, sizeof(escaped), "\\x%02X", c);
            result += escaped;
            ++i;
          }
        else
          {
            result.append(text, i, n);
            i += n;
          }
      }
    if (i < text.size())
      result += " [... " + std::to_string(text.size() - i) + " more bytes]";
    return result;
  }
} // namespace forma
