// The exported skeleton: rest orientations, the root bone and engine-style names.
//
// Orientation: a bone is drawn (Blender) and retargeted (Unity, VRM) along its joint's local +Y
// axis, so each joint's rest rotation turns +Y towards its child. The child is the only one when
// there is one, the limb's continuation where SMPL branches (pelvis → spine1, spine3 → neck),
// otherwise the mean of the children; a leaf (head, toes, finger tips) continues its parent's
// direction, and so does SMPL's hand joint: it sits on the knuckle line with the fingers'
// first joints beside it, so no child lies along the hand. The roll about the bone is fixed by keeping local +Z as
// close as possible to the body's forward axis (+Z), or to up (+Y) for a bone that itself points
// mostly forward (the feet), so left and right limbs get mirror-consistent frames.
#include "caliper/export/rig.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>

#include "caliper/errors.h"

namespace caliper {

namespace {

// A joint's preferred child where SMPL's tree branches: the joint the bone continues into.
const std::map<std::string, std::string>& preferred_child() {
  static const std::map<std::string, std::string> table = {
      {"pelvis", "spine1"}, {"spine3", "neck"}};
  return table;
}

bool continues_parent(const std::string& name) { return name == "left_hand" || name == "right_hand"; }

// The rotation whose +Y column is `along` (unit), with +Z nearest the forward axis.
Eigen::Matrix3d frame_along(const Eigen::Vector3d& along) {
  const Eigen::Vector3d hint = std::abs(along.z()) > 0.8 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d z = (hint - hint.dot(along) * along).normalized();
  Eigen::Matrix3d r;
  r.col(0) = along.cross(z);
  r.col(1) = along;
  r.col(2) = z;
  return r;
}

}  // namespace

SkeletonNaming parse_skeleton_naming(const std::string& text, const std::string& field) {
  if (text == "smpl") return SkeletonNaming::Smpl;
  if (text == "humanoid") return SkeletonNaming::Humanoid;
  throw Error(ErrorKind::InvalidArgument, field + " must be 'smpl' or 'humanoid', got '" + text + "'", field);
}

const char* to_string(SkeletonNaming naming) { return naming == SkeletonNaming::Smpl ? "smpl" : "humanoid"; }

const std::vector<HumanoidBone>& humanoid_bone_table() {
  // SMPL names its joints after the joint, not the bone it starts: `left_hip` starts the thigh,
  // `left_ankle` the foot, `left_foot` the toes, `left_collar` the shoulder (clavicle),
  // `left_shoulder` the upper arm, `left_wrist` the hand, `left_hand` the knuckles.
  static const std::vector<HumanoidBone> table = [] {
    std::vector<HumanoidBone> t = {
        {"pelvis", "Hips", "hips"},
        {"left_hip", "LeftUpperLeg", "leftUpperLeg"},
        {"right_hip", "RightUpperLeg", "rightUpperLeg"},
        {"spine1", "Spine", "spine"},
        {"left_knee", "LeftLowerLeg", "leftLowerLeg"},
        {"right_knee", "RightLowerLeg", "rightLowerLeg"},
        {"spine2", "Chest", "chest"},
        {"left_ankle", "LeftFoot", "leftFoot"},
        {"right_ankle", "RightFoot", "rightFoot"},
        {"spine3", "UpperChest", "upperChest"},
        {"left_foot", "LeftToes", "leftToes"},
        {"right_foot", "RightToes", "rightToes"},
        {"neck", "Neck", "neck"},
        {"left_collar", "LeftShoulder", "leftShoulder"},
        {"right_collar", "RightShoulder", "rightShoulder"},
        {"head", "Head", "head"},
        {"left_shoulder", "LeftUpperArm", "leftUpperArm"},
        {"right_shoulder", "RightUpperArm", "rightUpperArm"},
        {"left_elbow", "LeftLowerArm", "leftLowerArm"},
        {"right_elbow", "RightLowerArm", "rightLowerArm"},
        {"left_wrist", "LeftHand", "leftHand"},
        {"right_wrist", "RightHand", "rightHand"},
        {"left_hand", "LeftPalm", ""},
        {"right_hand", "RightPalm", ""},
    };
    // Fingers, SMPL-H order. Unity counts the thumb's bones Proximal/Intermediate/Distal from the
    // metacarpal; VRM 1.0 calls the same three Metacarpal/Proximal/Distal.
    static const std::vector<std::string> names = [] {
      std::vector<std::string> n;
      const std::pair<const char*, const char*> fingers[] = {
          {"index", "Index"}, {"middle", "Middle"}, {"pinky", "Little"}, {"ring", "Ring"}, {"thumb", "Thumb"}};
      const char* unity_segment[] = {"Proximal", "Intermediate", "Distal"};
      const char* vrm_thumb[] = {"Metacarpal", "Proximal", "Distal"};
      for (const auto& [side, Side] : {std::pair{"left", "Left"}, std::pair{"right", "Right"}})
        for (const auto& [finger, Finger] : fingers)
          for (int k = 0; k < 3; ++k) {
            n.push_back(std::string(side) + "_" + finger + std::to_string(k + 1));
            n.push_back(std::string(Side) + Finger + unity_segment[k]);
            n.push_back(std::string(side) + Finger + (std::string(finger) == "thumb" ? vrm_thumb[k] : unity_segment[k]));
          }
      return n;
    }();
    for (size_t i = 0; i < names.size(); i += 3)
      t.push_back({names[i].c_str(), names[i + 1].c_str(), names[i + 2].c_str()});
    return t;
  }();
  return table;
}

const HumanoidBone* find_humanoid_bone(const std::string& smpl_name) {
  for (const HumanoidBone& b : humanoid_bone_table())
    if (smpl_name == b.smpl) return &b;
  return nullptr;
}

Eigen::Matrix3d ExportRig::local_rotation(int j) const {
  const int p = parents[static_cast<size_t>(j)];
  const Eigen::Matrix3d& r = orientations[static_cast<size_t>(j)];
  return p < 0 ? r : Eigen::Matrix3d(orientations[static_cast<size_t>(p)].transpose() * r);
}

Eigen::Vector3d ExportRig::local_translation(int j) const {
  const int p = parents[static_cast<size_t>(j)];
  const Eigen::Vector3d& x = positions[static_cast<size_t>(j)];
  return p < 0 ? x : Eigen::Vector3d(orientations[static_cast<size_t>(p)].transpose() * (x - positions[static_cast<size_t>(p)]));
}

ExportRig export_rig(const BodyModel& model, const Eigen::MatrixX3d& joints, const Vertices& rest,
                     SkeletonNaming naming) {
  const int j_count = model.joint_count();
  if (joints.rows() != j_count)
    throw Error(ErrorKind::InvalidArgument,
                "export rig: " + std::to_string(joints.rows()) + " joints given, model has " + std::to_string(j_count),
                "joints");
  if (!joints.allFinite() || rest.rows() == 0 || !rest.allFinite())
    throw Error(ErrorKind::InvalidArgument, "export rig: joints or vertices contain NaN or infinity", "joints");
  const auto& data = model.data();
  ExportRig rig;
  rig.root = j_count;
  rig.model_names = data.joint_names;
  rig.model_names.push_back(kRootBoneSmplName);
  rig.parents = data.parents;
  rig.parents.push_back(-1);
  for (int j = 0; j < j_count; ++j) {
    rig.positions.push_back(joints.row(j).transpose());
    if (data.parents[static_cast<size_t>(j)] < 0) rig.parents[static_cast<size_t>(j)] = rig.root;
  }
  int model_root = 0;
  while (model_root < j_count && data.parents[static_cast<size_t>(model_root)] >= 0) ++model_root;
  const Eigen::Vector3d under = model_root < j_count ? rig.positions[static_cast<size_t>(model_root)] : Eigen::Vector3d::Zero();
  rig.positions.emplace_back(under.x(), rest.col(1).minCoeff(), under.z());

  for (const std::string& name : rig.model_names) {
    const HumanoidBone* b = find_humanoid_bone(name);
    if (naming == SkeletonNaming::Smpl) rig.names.push_back(name);
    else if (name == kRootBoneSmplName) rig.names.push_back(kRootBoneHumanoidName);
    else rig.names.push_back(b ? b->humanoid : name);
  }

  // Orientations parents first: the root bone, then the model's joints in tree order.
  const int n = rig.size();
  std::vector<std::vector<int>> children(static_cast<size_t>(n));
  for (int j = 0; j < n; ++j)
    if (rig.parents[static_cast<size_t>(j)] >= 0) children[static_cast<size_t>(rig.parents[static_cast<size_t>(j)])].push_back(j);
  rig.orientations.assign(static_cast<size_t>(n), Eigen::Matrix3d::Identity());
  std::vector<int> order = {rig.root};
  for (size_t k = 0; k < order.size(); ++k)
    for (int c : children[static_cast<size_t>(order[k])]) order.push_back(c);
  for (int j : order) {
    const auto& kids = children[static_cast<size_t>(j)];
    const int parent = rig.parents[static_cast<size_t>(j)];
    Eigen::Vector3d target = Eigen::Vector3d::Zero();
    const auto preferred = preferred_child().find(rig.model_names[static_cast<size_t>(j)]);
    const auto chosen = preferred == preferred_child().end()
                            ? kids.end()
                            : std::find_if(kids.begin(), kids.end(), [&](int c) { return rig.model_names[static_cast<size_t>(c)] == preferred->second; });
    if (chosen != kids.end()) target = rig.positions[static_cast<size_t>(*chosen)];
    else {
      for (int c : kids) target += rig.positions[static_cast<size_t>(c)];
      if (!kids.empty()) target /= static_cast<double>(kids.size());
    }
    const Eigen::Vector3d along = target - rig.positions[static_cast<size_t>(j)];
    if (!kids.empty() && along.norm() > 1e-9 && !continues_parent(rig.model_names[static_cast<size_t>(j)])) rig.orientations[static_cast<size_t>(j)] = frame_along(along.normalized());
    else if (parent >= 0) rig.orientations[static_cast<size_t>(j)] = rig.orientations[static_cast<size_t>(parent)];
  }
  return rig;
}

}  // namespace caliper
