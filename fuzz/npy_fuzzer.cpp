// One .npy document (src/io/npz.cpp, parse_npy): the header's dtype, shape and order, then the
// data. Oracles: an accepted array holds exactly as many values as its shape says, its strings
// are valid UTF-8, and the library's own writer round-trips it (numbers bit for bit).
#include <cstring>

#include "caliper/io/npz.h"
#include "caliper/utf8.h"
#include "fuzz_support.h"

using namespace caliper;

namespace {

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  npz::Array array;
  if (!fuzz::accepts([&] { array = npz::parse_npy(fuzz::as_string(data, size), "fuzz.npy"); })) return 0;
  if (array.is_object) return 0;  // pickled: listed, never read
  const bool text = !array.strings.empty() || array.dtype.find('U') != std::string::npos;
  const size_t held = text ? array.strings.size() : array.numbers.size();
  fuzz::check(static_cast<std::int64_t>(held) == array.size(), "value count differs from the shape's product");
  for (const auto& s : array.strings)
    fuzz::check(invalid_utf8_offset(s) == std::string_view::npos, "a decoded string is not valid UTF-8");

  npz::Array again;
  if (text) {
    if (!array.shape.empty()) return 0;  // the writer's 0-d form only
    fuzz::check(fuzz::accepts([&] { again = npz::parse_npy(npz::write_npy_unicode(array.strings.at(0)), "again"); }),
                "the writer's unicode array is refused");
    fuzz::check(again.strings == array.strings, "a unicode array changed in a round trip");
  } else {
    fuzz::check(fuzz::accepts([&] { again = npz::parse_npy(npz::write_npy_f64(array.numbers, array.shape), "again"); }),
                "the writer's float64 array is refused");
    fuzz::check(again.shape == array.shape && same_bits(again.numbers, array.numbers), "an array changed in a round trip");
  }
  return 0;
}
