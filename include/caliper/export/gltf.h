// glTF 2.0 binary (.glb) export of a rigged, skinned avatar: positions, normals, 4 joint
// influences per vertex, a joint node per SMPL joint (named after it), inverse bind matrices, and
// texture coordinates (TEXCOORD_0) when the model has a UV layout.
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
// With a UV layout, vertices on a seam are written once per UV they take (the first N are the
// model's, in order; copies follow), so the glb may have more vertices than the model.
std::string write_glb(const BodyModel& model, const Vertices& rest, const GlbOptions& options = {});
void save_glb(const std::string& path, const BodyModel& model, const Vertices& rest,
              const GlbOptions& options = {});

// Wavefront OBJ text (positions, normals, faces), metres.
std::string write_obj(const Vertices& vertices, const Faces& faces, const std::string& comment = {});
// The same with texture coordinates: `vt` lines from `uv` (U×2, OBJ convention, v up) and faces
// `f v/vt/vn` with `uv_faces` (F×3 into uv). Empty uv_faces writes no `vt` (as above).
std::string write_obj(const Vertices& vertices, const Faces& faces, const UvCoordinates& uv, const Faces& uv_faces,
                      const std::string& comment = {});
// The same written to `path`; throws Error(Io) naming the path when it cannot be written.
void save_obj(const std::string& path, const Vertices& vertices, const Faces& faces, const UvCoordinates& uv,
              const Faces& uv_faces, const std::string& comment = {});
Mesh read_obj(const std::string& path);  // triangles or polygons (fan-triangulated); throws Error

// An OBJ's mesh and, when every face corner has one, its texture coordinates (u, v; a `vt` with
// one number has v = 0), fan-triangulated like the faces. Empty uv_faces otherwise.
struct TexturedMesh {
  Mesh mesh;
  UvCoordinates uv_coordinates;  // U×2
  Faces uv_faces;                // F×3 into uv_coordinates, or empty
};
TexturedMesh read_obj_textured(const std::string& path);

}  // namespace caliper
