// The JSON report of an avatar (README "Report format"): model, sex, regressor, β, plausibility,
// and every measurement the model knows, requested beside achieved, in cm and kg; "warnings";
// with the "map" estimator also "uncertainty_cm"/"uncertainty_kg" per measurement (posterior SD)
// and an "uncertainty" object (noise setting, per-input fit, β SDs, vertex SD summary).
#pragma once
#include <string>

#include "caliper/avatar.h"

namespace caliper {

std::string avatar_report_json(const BodyModel& model, const Avatar& avatar, int indent = 2);

// Writes the avatar's rest-pose mesh as `path` says by its ending (case-insensitive): ".glb" (rigged
// glTF 2.0 binary; the map estimator's per-vertex SD as its _UNCERTAINTY attribute) or ".obj"
// (metres, with the model's UV layout). Throws Error(InvalidArgument) for another ending and
// Error(Io) when the file cannot be written, both naming `field` (the caller's name for the path).
void save_avatar(const std::string& path, const BodyModel& model, const Avatar& avatar,
                 const std::string& field = "path");
// True when `path` ends in .glb or .obj (any case): what save_avatar writes.
bool is_avatar_file_name(const std::string& path);

}  // namespace caliper
