// The skeleton as exported: the model's joints in the model's order (so SMPL pose data still
// indexes them), then a root bone on the floor under the pelvis; each joint given a rest
// orientation whose local +Y axis points at its child, and named after SMPL (the model's own
// names) or after the Unity Humanoid / VRM conventions engines map automatically.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "caliper/body/body_model.h"

namespace caliper {

enum class SkeletonNaming { Smpl, Humanoid };
// "smpl" or "humanoid"; anything else throws Error(InvalidArgument) naming `field`.
SkeletonNaming parse_skeleton_naming(const std::string& text, const std::string& field = "skeleton");
const char* to_string(SkeletonNaming naming);

// One row of the mapping between SMPL(-H) joint names and engine names. `humanoid` is Unity's
// HumanBodyBones name (also Mixamo-like); `vrm` the VRM 1.0 humanoid bone, or "" when VRM has
// no such bone (SMPL's hand joint sits at the knuckles, between VRM's hand and fingers).
struct HumanoidBone {
  const char* smpl;
  const char* humanoid;
  const char* vrm;
};
const std::vector<HumanoidBone>& humanoid_bone_table();  // SMPL's 24 joints, then SMPL-H's 30 fingers
const HumanoidBone* find_humanoid_bone(const std::string& smpl_name);  // nullptr when not in the table

constexpr const char* kRootBoneSmplName = "root";
constexpr const char* kRootBoneHumanoidName = "Root";

struct ExportRig {
  std::vector<std::string> names;            // J + 1: the model's joints, then the root bone
  std::vector<std::string> model_names;      // J + 1: the model's own names ("root" last)
  std::vector<int> parents;                  // J + 1, −1 for the root bone; the model's root hangs from it
  std::vector<Eigen::Vector3d> positions;    // world rest positions, metres
  std::vector<Eigen::Matrix3d> orientations; // world rest rotations: column 1 (local +Y) points at the child
  int root = 0;                              // index of the root bone (= the model's joint count)
  int size() const { return static_cast<int>(names.size()); }
  // Local rest transform of joint j relative to its parent (the world one for the root bone).
  Eigen::Matrix3d local_rotation(int j) const;
  Eigen::Vector3d local_translation(int j) const;
};

// `joints` (J×3) are the model's joints for these rest vertices; the root bone goes at the
// lowest vertex's height under the model's root joint. Throws Error(InvalidArgument) for
// non-finite joints or a joint count unlike the model's.
ExportRig export_rig(const BodyModel& model, const Eigen::MatrixX3d& joints, const Vertices& rest,
                     SkeletonNaming naming);

}  // namespace caliper
