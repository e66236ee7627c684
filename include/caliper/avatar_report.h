// The JSON report of an avatar (docs/cli.md "Report format"): model, sex, regressor, β, plausibility,
// and every measurement the model knows, requested beside achieved, in cm and kg, as a person
// measures them (a mapped measurement adds its rest-pose value, "rest_pose_cm"); "warnings";
// with the "map" estimator also "uncertainty_cm"/"uncertainty_kg" per measurement (posterior SD)
// and an "uncertainty" object (noise setting, per-input fit, β SDs, vertex SD summary).
#pragma once
#include <string>

#include "caliper/avatar.h"
#include "caliper/export/provenance.h"
#include "caliper/export/rig.h"

namespace caliper {

std::string avatar_report_json(const BodyModel& model, const Avatar& avatar, int indent = 2);

// What an exported file says about this avatar: the model's provenance, the regressor and the
// measurements as requested (SI).
Provenance avatar_provenance(const BodyModel& model, const Avatar& avatar);

// How save_avatar writes a rigged file: the bones' names, and the model's shape directions as
// morph targets (.glb and .vrm only).
struct AvatarFileOptions {
  SkeletonNaming skeleton = SkeletonNaming::Smpl;
  bool morphs = false;
};
// Writes the avatar's rest-pose mesh as `path` says by its ending (case-insensitive): ".glb"
// (rigged glTF 2.0 binary; the map estimator's per-vertex SD as its _UNCERTAINTY attribute),
// ".vrm" (VRM 1.0), ".fbx" (binary FBX 7.4) or ".obj" (metres, with the model's UV layout); the
// rigged files carry avatar_provenance(). Throws Error(InvalidArgument) for another ending or for
// morphs in a file that cannot carry them, and Error(Io) when the file cannot be written, naming
// `field` (the caller's name for the path).
void save_avatar(const std::string& path, const BodyModel& model, const Avatar& avatar,
                 const std::string& field = "path", const AvatarFileOptions& options = {});
// True when `path` ends in .glb, .vrm, .fbx or .obj (any case): what save_avatar writes.
bool is_avatar_file_name(const std::string& path);

}  // namespace caliper
