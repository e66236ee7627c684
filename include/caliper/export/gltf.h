// glTF 2.0 binary (.glb) export of a rigged, skinned avatar: positions, normals, 4 joint
// influences per vertex, a joint node per model joint plus a root bone on the floor (export/rig.h:
// rest orientations along the bones, SMPL or engine names), inverse bind matrices, texture
// coordinates (TEXCOORD_0) when the model has a UV layout, and the avatar's provenance
// (asset.copyright, asset.extras.caliper).
#pragma once
#include <string>
#include <vector>

#include "caliper/body/body_model.h"
#include "caliper/export/export_options.h"

namespace caliper {

struct GlbOptions : ExportOptions {
  std::vector<float> extra_vertex_scalar;  // optional N values written as _UNCERTAINTY
};

// GLB bytes for rest vertices (N×3) of `model`. Joints come from the model's joint regressor.
// With a UV layout, vertices on a seam are written once per UV they take (the first N are the
// model's, in order; copies follow), so the glb may have more vertices than the model.
std::string write_glb(const BodyModel& model, const Vertices& rest, const GlbOptions& options = {});
void save_glb(const std::string& path, const BodyModel& model, const Vertices& rest,
              const GlbOptions& options = {});

// VRM 1.0 (.vrm): the same GLB (always skinned) with the VRMC_vrm extension: the humanoid bone
// map (export/rig.h's table: every required bone and the fingers the model has), the
// first-person mesh, the look-at origin at the avatar's estimated eye point, and meta with the
// provenance and the use the body model's licence allows. Throws Error(Unsupported) naming the
// bone when the model lacks one VRM requires (hips, spine, head, legs, feet, arms, hands).
std::string write_vrm(const BodyModel& model, const Vertices& rest, const GlbOptions& options = {});
void save_vrm(const std::string& path, const BodyModel& model, const Vertices& rest,
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
