// Linear blend skinning with an SMPL-style pose: one axis-angle rotation per joint (radians),
// relative to the parent, applied about the joint's rest position; joint 0's is the global
// orientation. Pose correctives are not used (SPEC §3).
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "caliper/body/body_model.h"

namespace caliper {

using Pose = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;  // J×3 axis-angle, radians

Pose zero_pose(const BodyModel& model);  // the rest pose (our models' rest is a T-pose)
Pose t_pose(const BodyModel& model);     // same as zero_pose: arms horizontal
// Arms lowered by `degrees` from horizontal at the shoulders (45° is the usual A-pose).
Pose a_pose(const BodyModel& model, double degrees = 45.0);
// Mid-stride, to show the rig bending: left thigh forward and knee bent, right thigh back, arms
// lowered with the elbows bent. Joints the model lacks (by SMPL name) are left at rest.
Pose stride_pose(const BodyModel& model);

// Both hands closed into fists, the rest of the body at rest: every finger joint flexed towards
// the palm (knuckles 80°, middle joints 95°, last joints 60°) and the thumb folded across, for a
// model whose rest pose has the palms down and the thumbs forward (ours, SMPL's). A model without
// finger joints (SMPL, the MakeHuman body) bends its hand joints instead (SMPL's hand joint
// carries the fingers). Add it to another pose's rows for fists in that pose.
Pose fist_pose(const BodyModel& model);
// A pose given as SMPL-family axis-angle values (radians, three per joint), put on the model's
// joints by name: 72 values are SMPL's 24 joints, 156 SMPL-H's 52 (SMPL's first 22, then the 30
// finger joints; SMPL-H has no hand joints), 162 the built-in rig's 54 (rig_joint_names()), and
// otherwise 3·J values are the model's own joints in its order. Joints the values do not cover
// stay at rest; values for joints the model lacks (fingers on the MakeHuman body) are dropped.
// Throws Error(InvalidArgument, field "pose") for another count or a non-finite value.
Pose pose_from_axis_angles(const BodyModel& model, const std::vector<double>& values);
// The same from a JSON document: an array of numbers, an array of [x, y, z] triples, or an object
// whose "pose" member is either (AMASS's "poses" name is accepted too). At most 1 MiB. Throws
// Error(Format) naming `source` and what is wrong, Error(InvalidArgument) as above.
Pose pose_from_json(const BodyModel& model, const std::string& text, const std::string& source);
// Reads `path` (at most 1 MiB) and parses it with pose_from_json; Error(Io) if it cannot be read.
Pose load_pose(const BodyModel& model, const std::string& path);
// World transforms of every joint for a pose, given rest joints (J×3). 4×4 each.
std::vector<Eigen::Matrix4d> joint_world_transforms(const BodyModel& model,
                                                    const Eigen::MatrixX3d& rest_joints,
                                                    const Pose& pose);

// Joint positions (J×3) in a pose: each joint where joint_world_transforms puts it.
Eigen::MatrixX3d posed_joints(const BodyModel& model, const Eigen::MatrixX3d& rest_joints, const Pose& pose);
// Posed vertices (N×3) by linear blend skinning of rest vertices. Throws Error(InvalidArgument)
// if the pose has the wrong number of rows or a non-finite value.
Vertices pose_vertices(const BodyModel& model, const Vertices& rest, const Pose& pose);

}  // namespace caliper
