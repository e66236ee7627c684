// glTF 2.0 binary (.glb) export of a rigged, skinned avatar: positions, normals, 4 joint
// influences per vertex, a joint node per SMPL joint (named after it), inverse bind matrices.
#pragma once
#include <string>
#include <vector>

#include "caliper/body/body_model.h"

namespace caliper {

struct GlbOptions {
  std::string mesh_name = "avatar";
  bool include_skin = true;
  std::vector<float> extra_vertex_scalar;  // optional N values written as _UNCERTAINTY (issue 7)
};

// GLB bytes for rest vertices (N×3) of `model`. Joints come from the model's joint regressor.
std::string write_glb(const BodyModel& model, const Vertices& rest, const GlbOptions& options = {});
void save_glb(const std::string& path, const BodyModel& model, const Vertices& rest,
              const GlbOptions& options = {});

// Wavefront OBJ text (positions, normals, faces), metres.
std::string write_obj(const Vertices& vertices, const Faces& faces, const std::string& comment = {});
Mesh read_obj(const std::string& path);  // triangles or polygons (fan-triangulated); throws Error

}  // namespace caliper
