// MakeHuman morph targets (src/makehuman/assets.cpp, read_target): gzipped `index dx dy dz`
// lines. The input is the text, gzipped here so mutations reach the line parser; an input that
// starts with gzip's magic bytes is used as the file as it is. Oracles: every entry's vertex is
// inside the mesh and its displacement finite, one displacement per index.
#include <zlib.h>

#include <cmath>

#include "caliper/makehuman/assets.h"
#include "fuzz_support.h"

using namespace caliper;

namespace {

constexpr int kVertexCount = 64;  // the base mesh's size as read_target is told it

void write_gzipped(const std::string& path, const std::string& text) {
  gzFile f = gzopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (!text.empty()) gzwrite(f, text.data(), static_cast<unsigned>(text.size()));
  gzclose(f);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input = fuzz::as_string(data, size);
  const std::string path = (fuzz::scratch_dir() / "fuzz.target.gz").string();
  if (input.rfind("\x1f\x8b", 0) == 0) fuzz::write_scratch("fuzz.target.gz", input);
  else write_gzipped(path, input);
  makehuman::Target target;
  if (!fuzz::accepts([&] { target = makehuman::read_target(path, kVertexCount); })) return 0;
  fuzz::check(target.indices.size() == target.deltas.size(), "indices and displacements differ in number");
  for (size_t i = 0; i < target.indices.size(); ++i) {
    fuzz::check(target.indices[i] >= 0 && target.indices[i] < kVertexCount, "a vertex index outside the mesh");
    fuzz::check(target.deltas[i].allFinite(), "a non-finite displacement");
  }
  return 0;
}
