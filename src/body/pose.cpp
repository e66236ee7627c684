// Linear blend skinning with axis-angle joint rotations (SMPL, Loper et al. 2015, eq. 2–4,
// without pose blend shapes).
#include "caliper/body/pose.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "caliper/errors.h"
#include "gate.h"
#include "json_read.h"

namespace caliper {

namespace {

Eigen::Matrix3d rodrigues(const Eigen::Vector3d& axis_angle) {
  const double angle = axis_angle.norm();
  if (angle < 1e-12) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, axis_angle / angle).toRotationMatrix();
}

int joint_index(const BodyModel& model, const std::string& name) {
  const auto& names = model.data().joint_names;
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  return -1;
}

}  // namespace

Pose zero_pose(const BodyModel& model) { return Pose::Zero(model.joint_count(), 3); }
Pose t_pose(const BodyModel& model) { return zero_pose(model); }

Pose a_pose(const BodyModel& model, double degrees) {
  if (!std::isfinite(degrees) || degrees < -90 || degrees > 90)
    throw Error(ErrorKind::OutOfRange, "A-pose angle must be in [-90, 90] degrees", "degrees");
  Pose pose = zero_pose(model);
  const double a = degrees * M_PI / 180.0;
  // The left arm points to +X: a rotation of −a about +Z lowers it; the right arm mirrors that.
  if (int l = joint_index(model, "left_shoulder"); l >= 0) pose.row(l) << 0, 0, -a;
  if (int r = joint_index(model, "right_shoulder"); r >= 0) pose.row(r) << 0, 0, a;
  return pose;
}

Pose stride_pose(const BodyModel& model) {
  Pose pose = zero_pose(model);
  // Axis-angle per joint (radians). Legs hang along −Y and bend about X (a negative angle swings
  // the thigh forward, a positive one folds the shin back); arms point along ±X, are lowered
  // about Z and their forearms swing forward about Y.
  const std::pair<const char*, Eigen::Vector3d> rotations[] = {
      {"left_hip", {-0.5, 0, 0}},    {"left_knee", {0.75, 0, 0}},   {"right_hip", {0.3, 0, 0}},
      {"right_knee", {0.35, 0, 0}},  {"left_ankle", {0.15, 0, 0}},  {"left_shoulder", {0, 0, -1.15}},
      {"right_shoulder", {0, 0, 1.15}}, {"left_elbow", {0, -1.0, 0}}, {"right_elbow", {0, 0.8, 0}},
  };
  for (const auto& [name, r] : rotations)
    if (int j = joint_index(model, name); j >= 0) pose.row(j) = r.transpose();
  return pose;
}

Pose fist_pose(const BodyModel& model) {
  Pose pose = zero_pose(model);
  // Left hand (fingers along +X, palm down): flexion turns +X towards −Y, a rotation about −Z.
  // The thumb (along +X+Z, a little down) opposes: its first joint swings it under the palm about
  // the hand's long axis (+X) while it flexes, so the last two, flexing about the axis across the
  // thumb (~(0.55, 0, −0.85)) with a share about +X, lay it across the index and middle fingers
  // (flexing alone, it hooked forward beside the fist). Axis-angle vectors in degrees. The right
  // hand's axes are the mirror images (x kept, y and z negated: rotations are axial vectors).
  constexpr double kDeg = M_PI / 180;
  const Eigen::Vector3d finger_axis(0, 0, -1);
  const Eigen::Vector3d thumb[3] = {Eigen::Vector3d(70, 0, -25) * kDeg, Eigen::Vector3d(30, 0, -40) * kDeg,
                                    Eigen::Vector3d(30, 0, -45) * kDeg};
  auto mirrored = [](const Eigen::Vector3d& a) { return Eigen::Vector3d(a.x(), -a.y(), -a.z()); };
  constexpr double kFinger[3] = {95 * kDeg, 115 * kDeg, 75 * kDeg};  // knuckle, middle and end joints
  bool has_fingers = false;
  for (const char* side : {"left", "right"}) {
    const bool left = side[0] == 'l';
    for (const char* finger : {"index", "middle", "ring", "pinky", "thumb"})
      for (int k = 0; k < 3; ++k) {
        const int j = joint_index(model, std::string(side) + "_" + finger + std::to_string(k + 1));
        if (j < 0) continue;
        has_fingers = true;
        const Eigen::Vector3d r = finger[0] == 't' ? thumb[k] : Eigen::Vector3d(finger_axis * kFinger[k]);
        pose.row(j) = (left ? r : mirrored(r)).transpose();
      }
  }
  if (!has_fingers)
    for (const char* side : {"left", "right"})
      if (const int j = joint_index(model, std::string(side) + "_hand"); j >= 0)
        pose.row(j) = ((side[0] == 'l' ? finger_axis : mirrored(finger_axis)) * kFinger[0]).transpose();
  return pose;
}

namespace {

// The joint names a count of axis-angle values stands for (see pose_from_axis_angles).
std::vector<std::string> names_for_values(const BodyModel& model, size_t count) {
  if (count == 72) return smpl_joint_names();
  if (count == 156) {
    std::vector<std::string> names(smpl_joint_names().begin(), smpl_joint_names().begin() + 22);
    names.insert(names.end(), finger_joint_names().begin(), finger_joint_names().end());
    return names;
  }
  if (count == 3 * rig_joint_names().size()) return rig_joint_names();
  if (count == 3 * static_cast<size_t>(model.joint_count())) return model.data().joint_names;
  const size_t own = 3 * static_cast<size_t>(model.joint_count());
  const bool listed = own == 72 || own == 156 || own == 3 * rig_joint_names().size();
  throw Error(ErrorKind::InvalidArgument,
              "pose has " + std::to_string(count) + " values; expected 72 (SMPL), 156 (SMPL-H) or 162 (Caliper's rig)" +
                  (listed ? "" : " or " + std::to_string(own) + " (3 per joint of '" + model.name() + "')") +
                  ", axis-angle radians",
              "pose");
}

}  // namespace

Pose pose_from_axis_angles(const BodyModel& model, const std::vector<double>& values) {
  const std::vector<std::string> names = names_for_values(model, values.size());
  Pose pose = zero_pose(model);
  for (size_t i = 0; i < names.size(); ++i) {
    const Eigen::Vector3d r(values[3 * i], values[3 * i + 1], values[3 * i + 2]);
    if (!r.allFinite())
      throw Error(ErrorKind::InvalidArgument, "pose value for joint '" + names[i] + "' is not a finite number", "pose");
    if (const int j = joint_index(model, names[i]); j >= 0) pose.row(j) = r.transpose();
  }
  return pose;
}

Pose pose_from_json(const BodyModel& model, const std::string& text, const std::string& source) {
  constexpr size_t kMaxBytes = 1 << 20;
  const detail::JsonPlace doc{source, ""};
  if (text.size() > kMaxBytes) doc.fail("larger than 1 MiB; a pose is at most a few hundred numbers");
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) doc.fail("not valid JSON");
  const nlohmann::json* values = &j;
  detail::JsonPlace place = doc;
  if (j.is_object()) {
    const char* key = j.contains("pose") ? "pose" : "poses";
    place = doc / key;
    values = &detail::json_require(j, key, doc);
  }
  if (!values->is_array()) place.fail("must be an array of axis-angle numbers (radians) or of [x, y, z] triples");
  if (values->size() > 3 * 1000) place.fail("has " + std::to_string(values->size()) + " entries; a pose has at most a few hundred");
  std::vector<double> flat;
  for (size_t i = 0; i < values->size(); ++i) {
    const nlohmann::json& v = (*values)[i];
    const detail::JsonPlace at = place / std::to_string(i);
    if (v.is_array()) {
      if (v.size() != 3) at.fail("a joint's rotation must be 3 numbers [x, y, z]");
      for (size_t k = 0; k < 3; ++k) flat.push_back(detail::json_number(v[k], at / std::to_string(k)));
    } else {
      flat.push_back(detail::json_number(v, at));
    }
  }
  return pose_from_axis_angles(model, flat);
}

Pose load_pose(const BodyModel& model, const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorKind::Io, "cannot open pose file '" + path + "'", path);
  // A pose file is untrusted input: its gate (src/gate.h) lets only the library's errors out.
  return gate("pose file '" + path + "'", "pose", [&] {
    std::string text(1 << 20 | 1, '\0');
    in.read(text.data(), static_cast<std::streamsize>(text.size()));
    text.resize(static_cast<size_t>(in.gcount()));
    return pose_from_json(model, text, path);
  });
}

std::vector<Eigen::Matrix4d> joint_world_transforms(const BodyModel& model, const Eigen::MatrixX3d& rest_joints,
                                                    const Pose& pose) {
  const int nj = model.joint_count();
  if (pose.rows() != nj)
    throw Error(ErrorKind::InvalidArgument,
                "pose has " + std::to_string(pose.rows()) + " joints, model has " + std::to_string(nj), "pose");
  if (!pose.allFinite()) throw Error(ErrorKind::InvalidArgument, "pose contains NaN or infinity", "pose");
  const auto& parents = model.data().parents;
  std::vector<Eigen::Matrix4d> world(static_cast<size_t>(nj));
  for (int j = 0; j < nj; ++j) {
    Eigen::Matrix4d local = Eigen::Matrix4d::Identity();
    local.topLeftCorner<3, 3>() = rodrigues(pose.row(j).transpose());
    const int p = parents[static_cast<size_t>(j)];
    const Eigen::Vector3d offset = p < 0 ? Eigen::Vector3d(rest_joints.row(j).transpose())
                                         : Eigen::Vector3d((rest_joints.row(j) - rest_joints.row(p)).transpose());
    local.topRightCorner<3, 1>() = offset;
    world[static_cast<size_t>(j)] = p < 0 ? local : Eigen::Matrix4d(world[static_cast<size_t>(p)] * local);
  }
  return world;
}

Eigen::MatrixX3d posed_joints(const BodyModel& model, const Eigen::MatrixX3d& rest_joints, const Pose& pose) {
  const auto world = joint_world_transforms(model, rest_joints, pose);
  Eigen::MatrixX3d out(static_cast<Eigen::Index>(world.size()), 3);
  for (size_t j = 0; j < world.size(); ++j) out.row(static_cast<Eigen::Index>(j)) = world[j].topRightCorner<3, 1>().transpose();
  return out;
}

Vertices pose_vertices(const BodyModel& model, const Vertices& rest, const Pose& pose) {
  if (rest.rows() != model.vertex_count())
    throw Error(ErrorKind::InvalidArgument, "vertex count does not match the model", "vertices");
  const Eigen::MatrixX3d joints = model.joints(rest);
  auto world = joint_world_transforms(model, joints, pose);
  // Skinning transforms: undo the rest position of the joint, then apply its world transform.
  for (int j = 0; j < model.joint_count(); ++j) {
    const Eigen::Vector3d rest_j = joints.row(j).transpose();
    world[static_cast<size_t>(j)].topRightCorner<3, 1>() -= world[static_cast<size_t>(j)].topLeftCorner<3, 3>() * rest_j;
  }
  const auto& weights = model.data().skin_weights;
  Vertices out(rest.rows(), 3);
  for (Eigen::Index v = 0; v < rest.rows(); ++v) {
    Eigen::Matrix<double, 3, 4> blended = Eigen::Matrix<double, 3, 4>::Zero();
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(weights, v); it; ++it)
      blended += it.value() * world[static_cast<size_t>(it.col())].topRows<3>();
    out.row(v) = (blended.leftCols<3>() * rest.row(v).transpose() + blended.col(3)).transpose();
  }
  return out;
}

}  // namespace caliper
