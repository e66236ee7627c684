// Model files (src/io/model_files.cpp over src/io/npz.cpp), loaded the way `caliper model info
// FILE` loads them: native or SMPL/SMPL-X, told apart by the arrays inside. The input is the
// archive's entries (fuzz_support.h, "--npy NAME" lines), zipped here so mutations reach the
// model checks; an input starting "PK" is used as a zip file as it is. Oracle: a model that
// loads saves as a native file that loads back with the same arrays.
#include <optional>

#include "caliper/io/model_files.h"
#include "caliper/io/npz.h"
#include "fuzz_support.h"

using namespace caliper;

namespace {

template <class Sparse>
bool same_sparse(const Sparse& a, const Sparse& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && Sparse(a - b).norm() == 0;
}

bool same_model(const BodyModelData& a, const BodyModelData& b) {
  return a.sex == b.sex && a.template_vertices == b.template_vertices && a.faces == b.faces &&
         a.shape_directions == b.shape_directions && same_sparse(a.joint_regressor, b.joint_regressor) &&
         same_sparse(a.skin_weights, b.skin_weights) && a.joint_names == b.joint_names && a.parents == b.parents &&
         a.landmarks == b.landmarks && a.measurements.size() == b.measurements.size() &&
         a.uv_coordinates == b.uv_coordinates && a.uv_faces == b.uv_faces;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input = fuzz::as_string(data, size);
  const std::string path = (fuzz::scratch_dir() / "model.npz").string();
  if (input.rfind("PK", 0) == 0) {
    fuzz::write_scratch("model.npz", input);
  } else if (!fuzz::accepts([&] { npz::write_npz(path, fuzz::split_entries(input)); })) {
    return 0;  // entry names zip cannot hold: not an input a file could have
  }
  std::optional<BodyModel> model;
  if (!fuzz::accepts([&] { model.emplace(load_model(path, Sex::Neutral)); })) return 0;

  const std::string copy = (fuzz::scratch_dir() / "copy.npz").string();
  save_model(*model, copy);
  const BodyModel again = load_native_model(copy);
  fuzz::check(same_model(model->data(), again.data()), "a loaded model saved and read back differs");
  return 0;
}
