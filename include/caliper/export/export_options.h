// The options every avatar export (glb, vrm, fbx) takes.
#pragma once
#include <optional>
#include <string>

#include "caliper/export/provenance.h"
#include "caliper/export/rig.h"

namespace caliper {

struct ExportOptions {
  std::string mesh_name = "avatar";
  bool include_skin = true;
  SkeletonNaming skeleton = SkeletonNaming::Smpl;
  // Written into the file; without it, the model's part alone (model_provenance).
  std::optional<Provenance> provenance;
  // The model's shape directions as morph targets / blend shapes ("shape_0"…), weight 0, so an
  // engine can adjust the body live (weight w = β_k moved by w SD; the skeleton does not follow).
  // glTF and VRM: mesh morph targets; FBX: a BlendShape deformer with one channel per direction.
  bool morphs = false;
};

}  // namespace caliper
