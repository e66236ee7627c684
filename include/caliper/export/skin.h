// The skin a real-time client draws with: each vertex's 4 largest joint weights, renormalised,
// as the glTF, VRM and FBX writers write them (the virtual mirror skins the body in the browser).
#pragma once
#include <Eigen/Core>

#include "caliper/body/body_model.h"

namespace caliper {

struct SkinInfluences {
  Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor> joints;     // N×4 joint indices (the model's order)
  Eigen::Matrix<float, Eigen::Dynamic, 4, Eigen::RowMajor> weights;  // N×4, each row sums to 1 in float
};

SkinInfluences skin_influences(const BodyModel& model);

}  // namespace caliper
