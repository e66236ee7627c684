// The JSON report of an avatar (docs/cli.md "Report format"): model, sex, regressor, β, plausibility,
// and every measurement the model knows, requested beside achieved, in cm and kg, as a person
// measures them (a mapped measurement adds its rest-pose value, "rest_pose_cm"); "warnings";
// with the "map" estimator also "uncertainty_cm"/"uncertainty_kg" per measurement (posterior SD)
// and an "uncertainty" object (noise setting, per-input fit, β SDs, vertex SD summary).
#pragma once
#include <optional>
#include <string>

#include "caliper/avatar.h"
#include "caliper/export/provenance.h"
#include "caliper/export/rig.h"

namespace caliper {

std::string avatar_report_json(const BodyModel& model, const Avatar& avatar, int indent = 2);

// What an exported file says about this avatar: the model's provenance, the regressor and the
// measurements as requested (SI).
Provenance avatar_provenance(const BodyModel& model, const Avatar& avatar);

// The files an avatar is written as.
enum class AvatarFormat {
  Glb,  // rigged glTF 2.0 binary; the map estimator's per-vertex SD as its _UNCERTAINTY attribute
  Vrm,  // VRM 1.0 (glTF + VRMC_vrm)
  Fbx,  // rigged binary FBX 7.4
  Obj,  // the mesh only (metres, with the model's UV layout)
};
const char* to_string(AvatarFormat format);  // "glb", "vrm", "fbx", "obj"
// The format a name says ("glb", "vrm", "fbx", "obj", any case), or none.
std::optional<AvatarFormat> avatar_format_named(const std::string& name);
// True when `path` ends in .glb, .vrm, .fbx or .obj (any case): what save_avatar writes.
bool is_avatar_file_name(const std::string& path);
// The format `path` ends in; throws Error(InvalidArgument) naming `field` for another ending.
AvatarFormat avatar_file_format(const std::string& path, const std::string& field);

// The one rule for AvatarFileOptions::morphs: the rigged formats (glb, vrm, fbx) carry the
// model's shape directions as morph targets / blend shapes; an OBJ is a plain mesh.
bool avatar_format_carries_morphs(AvatarFormat format);

// How a rigged file is written: the bones' names, and the model's shape directions as morph
// targets (where avatar_format_carries_morphs).
struct AvatarFileOptions {
  SkeletonNaming skeleton = SkeletonNaming::Smpl;
  bool morphs = false;
};
// Throws Error(InvalidArgument) naming `field` when `options` ask for what `format` cannot hold
// (morphs in an OBJ). write_avatar and save_avatar check this first; a client may check it
// before building the avatar.
void check_avatar_file_options(AvatarFormat format, const AvatarFileOptions& options, const std::string& field);

// The avatar's rest-pose file in `format`; the rigged files carry avatar_provenance(). Throws
// as check_avatar_file_options (field "morphs") says.
std::string write_avatar(AvatarFormat format, const BodyModel& model, const Avatar& avatar,
                         const AvatarFileOptions& options = {});
// write_avatar in the format `path` ends in (case-insensitive). Throws Error(InvalidArgument)
// naming `field` (the caller's name for the path) for another ending or for options the format
// cannot hold, and Error(Io) when the file cannot be written.
void save_avatar(const std::string& path, const BodyModel& model, const Avatar& avatar,
                 const std::string& field = "path", const AvatarFileOptions& options = {});

}  // namespace caliper
