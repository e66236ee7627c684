#include "caliper/export/skin.h"

#include "export_common.h"

namespace caliper {

SkinInfluences skin_influences(const BodyModel& model) {
  const auto& skin = model.data().skin_weights;
  SkinInfluences out;
  out.joints.resize(skin.rows(), 4);
  out.weights.resize(skin.rows(), 4);
  for (Eigen::Index v = 0; v < skin.rows(); ++v) {
    const export_detail::Influences inf = export_detail::top_influences(skin, v);
    for (int k = 0; k < 4; ++k) {
      out.joints(v, k) = inf.joints[static_cast<size_t>(k)];
      out.weights(v, k) = inf.weights[static_cast<size_t>(k)];
    }
  }
  return out;
}

}  // namespace caliper
