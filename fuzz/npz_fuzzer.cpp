// Whole .npz archives as they arrive (src/io/npz.cpp, read_npz): the zip directory, each entry's
// .npy header and its inflated data, under read limits. The limits here are a 64th of the
// defaults (same checks, less memory per run). Oracles: every accepted array respects the limits,
// and writing the numeric arrays back with the library's writer reads back the same.
#include <cctype>
#include <cstring>

#include "caliper/io/npz.h"
#include "fuzz_support.h"

using namespace caliper;

namespace {

npz::ReadLimits fuzz_limits() {
  const npz::ReadLimits defaults;
  npz::ReadLimits l;
  l.array_values = defaults.array_values / 64;
  l.entry_bytes = defaults.entry_bytes / 64;
  l.archive_values = defaults.archive_values / 64;
  l.archive_bytes = defaults.archive_bytes / 64;
  l.entries = defaults.entries;
  return l;
}

// Entry names the round trip can rewrite unchanged (zip paths may hold anything).
bool plain_name(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const npz::ReadLimits limits = fuzz_limits();
  const std::string path = fuzz::write_scratch("archive.npz", fuzz::as_string(data, size));
  std::map<std::string, npz::Array> arrays;
  if (!fuzz::accepts([&] { arrays = npz::read_npz(path, limits); })) return 0;

  fuzz::check(static_cast<std::int64_t>(arrays.size()) <= limits.entries, "more entries than the limit");
  std::int64_t total = 0;
  std::map<std::string, std::string> rewritten;
  for (const auto& [name, a] : arrays) {
    fuzz::check(a.size() <= limits.array_values, "an array beyond the value limit: " + name);
    total += static_cast<std::int64_t>(a.numbers.size() + a.strings.size());
    if (!a.is_object && a.strings.empty() && plain_name(name)) rewritten[name] = npz::write_npy_f64(a.numbers, a.shape);
  }
  fuzz::check(total <= limits.archive_values, "an archive beyond the value limit");

  if (rewritten.empty()) return 0;  // nothing plain to round-trip (and write_npz refuses an empty archive)
  const std::string copy = (fuzz::scratch_dir() / "copy.npz").string();
  npz::write_npz(copy, rewritten);
  const auto again = npz::read_npz(copy, limits);
  fuzz::check(again.size() == rewritten.size(), "entries lost in a round trip");
  for (const auto& [name, a] : again) {
    const npz::Array& before = arrays.at(name);
    fuzz::check(a.shape == before.shape && a.numbers.size() == before.numbers.size() &&
                    (a.numbers.empty() ||
                     std::memcmp(a.numbers.data(), before.numbers.data(), a.numbers.size() * sizeof(double)) == 0),
                "array '" + name + "' changed in a round trip");
  }
  return 0;
}
