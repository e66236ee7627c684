// One MakeHuman body from slider values, posed into Caliper's frame: base + Σ weight·delta over
// the macro and measure targets (linear in the deltas), the A-pose rest turned into a T-pose by
// rotating each arm chain of the cmu_mb rig to the horizontal (linear blend skinning with the
// rig's own weights), feet put on y = 0. The rig's 31 bones map onto SMPL's 24 joints.
#pragma once
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <map>
#include <string>
#include <vector>

#include "caliper/body/mesh.h"
#include "caliper/makehuman/assets.h"
#include "caliper/makehuman/macro.h"

namespace caliper::makehuman {

struct Shape {
  MacroSliders macro;
  std::map<std::string, double> modifiers;  // "measure-waist-circ" → v ∈ [−1, 1]; absent = 0
};

// Names of the signed measure modifiers found in the assets ("measure-bust-circ", …), sorted.
std::vector<std::string> modifier_names(const Assets& assets);

// All base-mesh vertices (body, helpers, joint cubes) for a shape, A-pose, metres, the asset's
// frame. Throws Error(OutOfRange) naming a slider outside its range.
Vertices morph(const Assets& assets, const Shape& shape);

// For each of the rig's bones, the SMPL joint (index into smpl_joint_names()) its weights and
// head belong to: cmu_mb has extra bones (hip joints, a second neck bone, finger bones) that
// merge into SMPL's pelvis, neck and hands. Throws Error(Format) naming a bone it cannot place.
std::vector<int> smpl_joint_of_bones(const Rig& rig);
// The cmu_mb bone whose head is each SMPL joint (24 names, SMPL order).
const std::vector<std::string>& smpl_joint_bones();

struct PosedBody {
  Vertices body;                // kBodyVertexCount×3, T-pose, feet on y = 0, metres, facing +Z
  Eigen::MatrixX3d joints;      // 24×3 SMPL-order joints from the rig's joint definitions, same frame
};

// Turns a morphed A-pose body (all vertices, from morph()) into the T-pose: the upper arm,
// forearm and hand of each side rotate about their joints (shortest rotation) until each bone
// points along ±X; vertices follow by linear blend skinning with the rig's weights.
PosedBody t_pose(const Assets& assets, const Vertices& all_vertices);

// Skin weights of the body vertices on SMPL's 24 joints (rows sum to 1).  kBodyVertexCount×24.
Eigen::SparseMatrix<double, Eigen::RowMajor> smpl_skin_weights(const Assets& assets);

}  // namespace caliper::makehuman
