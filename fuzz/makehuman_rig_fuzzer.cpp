// MakeHuman rigs (src/makehuman/assets.cpp, read_rig): rig.<name>.json (bones, their parents
// and joint strategies) and weights.<name>.json, read against a base mesh. The input is the rig
// JSON, then a line "--weights", then the weights JSON; the mesh is a fixed 8-vertex one with
// two joint cubes. Oracles: bones come parents first, every joint vertex is in the mesh, and
// every vertex's weights name real bones, are positive and sum to 1.
#include <cmath>

#include "caliper/makehuman/assets.h"
#include "fuzz_support.h"

using namespace caliper;

namespace {

const makehuman::BaseMesh& mesh() {
  static const makehuman::BaseMesh m = [] {
    makehuman::BaseMesh b;
    b.vertices = Vertices::Zero(8, 3);
    for (int v = 0; v < 8; ++v) b.vertices(v, 1) = 0.1 * v;
    b.groups = {{"joint-root", {0, 1, 2, 3}}, {"joint-tip", {4, 5, 6, 7}}};
    return b;
  }();
  return m;
}

void check_joint(const std::vector<int>& vertices) {
  fuzz::check(!vertices.empty(), "a joint without vertices");
  for (int v : vertices) fuzz::check(v >= 0 && v < mesh().vertices.rows(), "a joint vertex outside the mesh");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input = fuzz::as_string(data, size);
  const size_t split = input.find("\n--weights\n");
  const std::string rig_json = input.substr(0, split);
  const std::string weights_json = split == std::string::npos ? std::string() : input.substr(split + 11);
  fuzz::write_scratch("rigs/standard/rig.fuzz.json", rig_json);
  fuzz::write_scratch("rigs/standard/weights.fuzz.json", weights_json);

  makehuman::Rig rig;
  if (!fuzz::accepts([&] { rig = makehuman::read_rig(fuzz::scratch_dir().string(), mesh(), "fuzz"); })) return 0;
  for (size_t b = 0; b < rig.bones.size(); ++b) {
    const auto& bone = rig.bones[b];
    const int parent = rig.bone_index(bone.parent);
    fuzz::check(bone.parent.empty() || (parent >= 0 && static_cast<size_t>(parent) < b), "a bone before its parent");
    check_joint(bone.head_vertices);
    check_joint(bone.tail_vertices);
  }
  fuzz::check(rig.weights.size() == static_cast<size_t>(mesh().vertices.rows()), "weights not one list per vertex");
  for (const auto& list : rig.weights) {
    double sum = 0;
    for (const auto& [bone, w] : list) {
      fuzz::check(bone >= 0 && static_cast<size_t>(bone) < rig.bones.size(), "a weight for a bone that does not exist");
      fuzz::check(std::isfinite(w) && w > 0, "a weight that is not positive and finite");
      sum += w;
    }
    fuzz::check(list.empty() || std::abs(sum - 1) < 1e-4, "a vertex's weights do not sum to 1");
  }
  return 0;
}
