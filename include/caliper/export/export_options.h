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
};

}  // namespace caliper
