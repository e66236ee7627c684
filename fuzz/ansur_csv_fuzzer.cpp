// ANSUR II and plain anthropometry CSV (src/io/ansur.cpp, parse_ansur_csv), and the six
// Virtual Caliper inputs taken from each subject. The library has no writer for this format, so
// the oracle is the reader's contract: every value is finite, and the inputs either come out
// finite or are refused with caliper::Error.
#include <cmath>

#include "caliper/io/ansur.h"
#include "fuzz_support.h"

using namespace caliper;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<AnsurSubject> subjects;
  if (!fuzz::accepts([&] { subjects = parse_ansur_csv(fuzz::as_string(data, size), "fuzz.csv"); })) return 0;
  for (const auto& s : subjects) {
    for (const auto& [column, value] : s.values) fuzz::check(std::isfinite(value), "non-finite value in " + column);
    std::map<std::string, double> inputs;
    if (!fuzz::accepts([&] { inputs = virtual_caliper_inputs(s); })) continue;
    for (const auto& [name, value] : inputs) fuzz::check(std::isfinite(value), "non-finite input " + name);
  }
  return 0;
}
