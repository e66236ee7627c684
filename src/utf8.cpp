// UTF-8 decoding per RFC 3629 §3–4 (no overlong forms, no surrogates, nothing above U+10FFFF).
#include "caliper/utf8.h"

namespace caliper {

bool next_code_point(std::string_view text, std::size_t& i, std::uint32_t& cp) {
  if (i >= text.size()) return false;
  const auto lead = static_cast<unsigned char>(text[i]);
  std::size_t extra;
  std::uint32_t value;
  if (lead < 0x80) { value = lead; extra = 0; }
  else if ((lead & 0xE0) == 0xC0) { value = lead & 0x1F; extra = 1; }
  else if ((lead & 0xF0) == 0xE0) { value = lead & 0x0F; extra = 2; }
  else if ((lead & 0xF8) == 0xF0) { value = lead & 0x07; extra = 3; }
  else return false;
  if (extra >= text.size() - i) return false;  // cut short
  for (std::size_t k = 1; k <= extra; ++k) {
    const auto c = static_cast<unsigned char>(text[i + k]);
    if ((c & 0xC0) != 0x80) return false;
    value = (value << 6) | (c & 0x3F);
  }
  static constexpr std::uint32_t kShortest[] = {0, 0x80, 0x800, 0x10000};
  if (value < kShortest[extra] || value > 0x10FFFF || (value >= 0xD800 && value <= 0xDFFF)) return false;
  cp = value;
  i += extra + 1;
  return true;
}

std::size_t invalid_utf8_offset(std::string_view text) {
  std::size_t i = 0;
  std::uint32_t cp;
  while (i < text.size())
    if (!next_code_point(text, i, cp)) return i;
  return std::string_view::npos;
}

}  // namespace caliper
