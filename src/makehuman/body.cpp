// A MakeHuman body for given sliders, and its T-pose in Caliper's frame.
// Morphing: assets README (body = base + Σ weight·delta). Posing: linear blend skinning with the
// cmu_mb weights, each arm bone rotated by the shortest rotation onto ±X (our own T-pose).
#include "caliper/makehuman/body.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "caliper/body/body_model.h"
#include "caliper/errors.h"

namespace caliper::makehuman {

namespace {

// cmu_mb bone → SMPL joint name (the joint the bone rotates about, SMPL's convention).
const std::map<std::string, std::string>& bone_to_joint() {
  static const std::map<std::string, std::string> m = {
      {"Hips", "pelvis"},           {"LHipJoint", "pelvis"},        {"RHipJoint", "pelvis"},
      {"LeftUpLeg", "left_hip"},    {"RightUpLeg", "right_hip"},    {"LowerBack", "spine1"},
      {"LeftLeg", "left_knee"},     {"RightLeg", "right_knee"},     {"Spine", "spine2"},
      {"LeftFoot", "left_ankle"},   {"RightFoot", "right_ankle"},   {"Spine1", "spine3"},
      {"LeftToeBase", "left_foot"}, {"RightToeBase", "right_foot"}, {"Neck", "neck"},
      {"Neck1", "neck"},            {"LeftShoulder", "left_collar"}, {"RightShoulder", "right_collar"},
      {"Head", "head"},             {"LeftArm", "left_shoulder"},   {"RightArm", "right_shoulder"},
      {"LeftForeArm", "left_elbow"}, {"RightForeArm", "right_elbow"}, {"LeftHand", "left_wrist"},
      {"RightHand", "right_wrist"}, {"LeftFingerBase", "left_hand"}, {"RightFingerBase", "right_hand"},
      {"LeftHandFinger1", "left_hand"}, {"RightHandFinger1", "right_hand"}, {"LThumb", "left_hand"},
      {"RThumb", "right_hand"}};
  return m;
}

Eigen::Vector3d mean_of(const Vertices& v, const std::vector<int>& idx) {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (int i : idx) s += v.row(i).transpose();
  return s / static_cast<double>(idx.size());
}

struct Affine {  // x → r·x + t
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::Vector3d operator()(const Eigen::Vector3d& x) const { return r * x + t; }
};

// parent ∘ (rotation about `centre` taking direction `from` onto `to`).
Affine rotate_about(const Affine& parent, const Eigen::Vector3d& centre, const Eigen::Vector3d& from,
                    const Eigen::Vector3d& to) {
  const Eigen::Matrix3d r = Eigen::Quaterniond::FromTwoVectors(from, to).toRotationMatrix();
  // y = parent(x); z = r (y − c) + c, where c = parent(centre_rest) = centre (already posed).
  Affine a;
  a.r = r * parent.r;
  a.t = r * (parent.t - centre) + centre;
  return a;
}

}  // namespace

std::vector<std::string> modifier_names(const Assets& assets) {
  std::vector<std::string> names;
  for (const auto& t : assets.modifier_targets) {
    const std::string base = t.name.substr(0, t.name.size() - 5);  // drop -incr / -decr
    if (std::find(names.begin(), names.end(), base) == names.end()) names.push_back(base);
  }
  std::sort(names.begin(), names.end());
  return names;
}

Vertices morph(const Assets& assets, const Shape& shape) {
  const auto tokens = token_weights(shape.macro);
  for (const auto& [name, v] : shape.modifiers)
    if (!std::isfinite(v) || v < -1 || v > 1) throw Error(ErrorKind::OutOfRange, "modifier " + name + " must be in [-1, 1]", name);
  Vertices out = assets.mesh.vertices;
  auto add = [&](const Target& t, double w) {
    if (std::abs(w) < 1e-12) return;
    for (size_t i = 0; i < t.indices.size(); ++i) {
      auto row = out.row(t.indices[i]);
      row(0) += w * t.deltas[i](0);
      row(1) += w * t.deltas[i](1);
      row(2) += w * t.deltas[i](2);
    }
  };
  for (const auto& t : assets.macro_targets) add(t, target_weight(t.name, tokens));
  for (const auto& t : assets.modifier_targets) add(t, modifier_weight(t.name, shape.modifiers));
  return out;
}

const std::vector<std::string>& smpl_joint_bones() {
  static const std::vector<std::string> bones = {
      "Hips",        "LeftUpLeg",  "RightUpLeg",   "LowerBack",    "LeftLeg",      "RightLeg",
      "Spine",       "LeftFoot",   "RightFoot",    "Spine1",       "LeftToeBase",  "RightToeBase",
      "Neck",        "LeftShoulder", "RightShoulder", "Head",      "LeftArm",      "RightArm",
      "LeftForeArm", "RightForeArm", "LeftHand",   "RightHand",    "LeftFingerBase", "RightFingerBase"};
  return bones;
}

std::vector<int> smpl_joint_of_bones(const Rig& rig) {
  const auto& names = smpl_joint_names();
  std::vector<int> out;
  for (const auto& b : rig.bones) {
    auto it = bone_to_joint().find(b.name);
    if (it == bone_to_joint().end())
      throw Error(ErrorKind::Format, "rig bone '" + b.name + "' has no SMPL joint (expected the cmu_mb skeleton)", b.name);
    out.push_back(static_cast<int>(std::find(names.begin(), names.end(), it->second) - names.begin()));
  }
  return out;
}

PosedBody t_pose(const Assets& assets, const Vertices& v) {
  const Rig& rig = assets.rig;
  const size_t nb = rig.bones.size();
  std::vector<Affine> transform(nb);
  auto bone = [&](const std::string& name) {
    const int i = rig.bone_index(name);
    if (i < 0) throw Error(ErrorKind::Format, "rig has no bone '" + name + "' (expected the cmu_mb skeleton)", name);
    return i;
  };
  auto head = [&](int b) { return mean_of(v, rig.bones[static_cast<size_t>(b)].head_vertices); };
  auto tail = [&](int b) { return mean_of(v, rig.bones[static_cast<size_t>(b)].tail_vertices); };
  for (const auto& [side, sign] : {std::pair<std::string, double>{"Left", 1.0}, {"Right", -1.0}}) {
    const Eigen::Vector3d out_dir(sign, 0, 0);
    // Upper arm, forearm, hand: each bone's head→tail direction onto ±X, children following.
    Affine parent;
    for (const std::string& name : {side + "Arm", side + "ForeArm", side + "Hand"}) {
      const int b = bone(name);
      const Eigen::Vector3d h = parent(head(b)), t = parent(tail(b));
      transform[static_cast<size_t>(b)] = rotate_about(parent, h, (t - h).normalized(), out_dir);
      parent = transform[static_cast<size_t>(b)];
    }
  }
  // Descendants of a posed bone inherit its transform (fingers, thumb).
  for (size_t b = 0; b < nb; ++b) {
    const std::string& p = rig.bones[b].parent;
    if (p.empty()) continue;
    const bool own = transform[b].r != Eigen::Matrix3d::Identity() || !transform[b].t.isZero();
    if (!own) transform[b] = transform[static_cast<size_t>(rig.bone_index(p))];
  }
  PosedBody out;
  out.body.resize(kBodyVertexCount, 3);
  for (int i = 0; i < kBodyVertexCount; ++i) {
    const Eigen::Vector3d x = v.row(i).transpose();
    Eigen::Vector3d y = Eigen::Vector3d::Zero();
    for (const auto& [b, w] : rig.weights[static_cast<size_t>(i)]) y += static_cast<double>(w) * transform[static_cast<size_t>(b)](x);
    out.body.row(i) = y.transpose();
  }
  const auto& joint_bones = smpl_joint_bones();
  out.joints.resize(static_cast<Eigen::Index>(joint_bones.size()), 3);
  for (size_t j = 0; j < joint_bones.size(); ++j) {
    const int b = bone(joint_bones[j]);
    out.joints.row(static_cast<Eigen::Index>(j)) = transform[static_cast<size_t>(b)](head(b)).transpose();
  }
  const double floor = out.body.col(1).minCoeff();
  out.body.col(1).array() -= floor;
  out.joints.col(1).array() -= floor;
  return out;
}

Eigen::SparseMatrix<double, Eigen::RowMajor> smpl_skin_weights(const Assets& assets) {
  const std::vector<int> joint_of = smpl_joint_of_bones(assets.rig);
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < kBodyVertexCount; ++i) {
    std::map<int, double> per_joint;
    for (const auto& [b, w] : assets.rig.weights[static_cast<size_t>(i)]) per_joint[joint_of[static_cast<size_t>(b)]] += w;
    double s = 0;
    for (const auto& [j, w] : per_joint) s += w;
    for (const auto& [j, w] : per_joint) t.emplace_back(i, j, w / s);
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor> m(kBodyVertexCount, static_cast<Eigen::Index>(smpl_joint_names().size()));
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

}  // namespace caliper::makehuman
