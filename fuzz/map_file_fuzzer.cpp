// Real → virtual map files (src/protocol/real_to_virtual.cpp, RealToVirtual::from_json), the
// JSON `caliper avatar --map` reads. Oracles: every accepted map can be applied and inverted
// (finite, positive slope), and to_json's output reads back to the same maps.
#include <algorithm>
#include <cmath>

#include "caliper/protocol/real_to_virtual.h"
#include "fuzz_support.h"

using namespace caliper;

namespace {

bool close(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max({1.0, std::abs(a), std::abs(b)}); }

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  RealToVirtual maps;
  if (!fuzz::accepts([&] { maps = RealToVirtual::from_json(fuzz::as_string(data, size)); })) return 0;
  for (const auto& [name, m] : maps.maps())
    fuzz::check(std::isfinite(m.slope) && m.slope > 0 && std::isfinite(m.offset) && std::isfinite(m.rmse) && m.pairs >= 0,
                "map " + name + " cannot be applied");

  RealToVirtual again;
  fuzz::check(fuzz::accepts([&] { again = RealToVirtual::from_json(maps.to_json()); }),
              "the library refuses its own map file:\n" + maps.to_json());
  fuzz::check(again.maps().size() == maps.maps().size(), "maps lost in a round trip");
  for (const auto& [name, m] : maps.maps()) {
    const LinearMap& n = again.map(name);
    fuzz::check(close(n.slope, m.slope) && close(n.offset, m.offset) && n.pairs == m.pairs && close(n.rmse, m.rmse),
                "map " + name + " changed in a round trip");
  }
  return 0;
}
