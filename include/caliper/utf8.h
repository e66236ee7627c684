// UTF-8 checks for untrusted text (file contents, HTTP bodies): one decoder for every place that
// must refuse malformed text before quoting or storing it.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace caliper {

// Decodes the code point starting at text[i] into `cp` and moves i past it. Returns false, with
// i unchanged, for a malformed, truncated or overlong sequence, a surrogate (U+D800–DFFF) or a
// value beyond U+10FFFF.
bool next_code_point(std::string_view text, std::size_t& i, std::uint32_t& cp);

// The offset of the first byte that does not start a valid UTF-8 sequence, or
// std::string_view::npos when all of `text` is valid.
std::size_t invalid_utf8_offset(std::string_view text);

}  // namespace caliper
