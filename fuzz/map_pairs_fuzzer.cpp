// Paired real/virtual measurements (src/protocol/real_to_virtual.cpp, RealToVirtual::fit_csv):
// the plain CSV `caliper map fit` fits maps from (measurement,real_cm,virtual_cm). Oracles: every
// fitted map is usable (finite, positive slope, at least 3 pairs) and survives its own file
// format.
#include <cmath>

#include "caliper/protocol/real_to_virtual.h"
#include "fuzz_support.h"

using namespace caliper;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = fuzz::write_scratch("pairs.csv", fuzz::as_string(data, size));
  RealToVirtual maps;
  if (!fuzz::accepts([&] { maps = RealToVirtual::fit_csv(path); })) return 0;
  for (const auto& [name, m] : maps.maps())
    fuzz::check(std::isfinite(m.slope) && m.slope > 0 && std::isfinite(m.offset) && std::isfinite(m.rmse) && m.pairs >= 3,
                "fitted map " + name + " is not usable");
  RealToVirtual again;
  fuzz::check(fuzz::accepts([&] { again = RealToVirtual::from_json(maps.to_json()); }),
              "the library refuses the map file it wrote:\n" + maps.to_json());
  fuzz::check(again.maps().size() == maps.maps().size(), "maps lost when written");
  return 0;
}
