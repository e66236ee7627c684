// Autodesk FBX binary (version 7.4) export of a rigged, skinned avatar, written by Caliper's own
// code: mesh with normals and texture coordinates, one LimbNode per exported joint (export/rig.h:
// the model's joints and the root bone, rest orientations along the bones), a skin with one
// cluster per joint, a bind pose, the avatar's provenance and, with `morphs`, the model's shape
// directions as blend shapes (one channel "shape_k" each, at 0 %). Metres, +Y up, facing +Z, declared
// in GlobalSettings so Blender, Unity and Unreal import at the right size and orientation.
#pragma once
#include <string>

#include "caliper/body/body_model.h"
#include "caliper/export/export_options.h"

namespace caliper {

// FBX bytes for rest vertices (N×3) of `model`. Throws Error(InvalidArgument) for a vertex count
// unlike the model's or non-finite vertices.
std::string write_fbx(const BodyModel& model, const Vertices& rest, const ExportOptions& options = {});
void save_fbx(const std::string& path, const BodyModel& model, const Vertices& rest, const ExportOptions& options = {});

}  // namespace caliper
