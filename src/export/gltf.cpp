// glTF 2.0 binary export of a rigged, skinned avatar, and Wavefront OBJ write/read.
//
// The avatar is exported in its rest pose with linear-blend skinning (paper §3.4.1 and §5: the
// paper exports a rigged FBX for Unity; glTF 2.0 is our primary format). glTF's frame is ours:
// metres, +Y up, +Z forward, so no conversion is needed.
//
// Layout of the .glb (chosen so Blender, Unity/glTFast, three.js and the Khronos validator agree):
//   nodes 0..J-1   one per joint, named after the model's joints, children per `parents`,
//                  translation relative to the parent (the root's is absolute), no rotation;
//   node  J        the skinned mesh node: a scene root with no transform, as the spec
//                  recommends (a skinned mesh ignores its parents' transforms);
//   node  J+1      "Armature": a scene root holding the root joint, which Blender turns into
//                  the armature object.
// One skin with inverse bind matrices (the inverse of each joint's rest world transform, i.e. a
// translation by −joint position), skeleton = the root joint. Each vertex keeps its 4 largest
// skin weights, renormalised so they sum to exactly 1 in float.
//
// Texture coordinates: a model's UV layout is OBJ-style (a vertex on a seam has one UV per
// island), glTF's is per vertex. So the mesh is split: vertices 0..N−1 are the model's, each
// with the UV of its first corner in face order, and every further (vertex, UV) pair a corner
// uses is appended as a copy of its vertex (position, normal, skin, _UNCERTAINTY). Normals are
// computed on the unsplit mesh, so shading has no seam. TEXCOORD_0 = (u, 1 − v): glTF's UV origin
// is the image's top-left corner, OBJ's the bottom-left.
#include "caliper/export/gltf.h"

#include <tiny_gltf.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>
#include <utility>

#include <nlohmann/json.hpp>

#include "caliper/errors.h"
#include "export_common.h"

#ifndef CALIPER_VERSION
#define CALIPER_VERSION "unknown"
#endif

namespace caliper {

using export_detail::Influences;
using export_detail::top_influences;
using export_detail::write_file;

namespace {

// glTF enums (spec §5.1, §3.7.2).
constexpr int kArrayBuffer = 34962;
constexpr int kElementArrayBuffer = 34963;
constexpr int kTriangles = 4;

// Neutral matte skin tone, linear RGB (≈ sRGB 224, 172, 145): light enough to show the shape.
constexpr std::array<double, 4> kSkinColour = {0.745, 0.412, 0.283, 1.0};

// Appends raw values to the single binary buffer and records a buffer view for them.
class BinaryBuilder {
 public:
  explicit BinaryBuilder(tinygltf::Model& model) : model_(model) {}

  template <class T>
  int add_view(const std::vector<T>& values, int target) {
    // Every view starts on a 4-byte boundary, which satisfies the alignment of all component
    // types and the vertex-attribute rule (offsets multiple of 4).
    while (data_.size() % 4 != 0) data_.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data_.size();
    view.byteLength = values.size() * sizeof(T);
    view.target = target;
    const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
    data_.insert(data_.end(), bytes, bytes + view.byteLength);
    model_.bufferViews.push_back(std::move(view));
    return static_cast<int>(model_.bufferViews.size()) - 1;
  }

  template <class T>
  int add_accessor(const std::vector<T>& values, int component_type, int type, size_t count,
                   int target, std::vector<double> min = {}, std::vector<double> max = {}) {
    tinygltf::Accessor accessor;
    accessor.bufferView = add_view(values, target);
    accessor.byteOffset = 0;
    accessor.componentType = component_type;
    accessor.type = type;
    accessor.count = count;
    accessor.minValues = std::move(min);
    accessor.maxValues = std::move(max);
    model_.accessors.push_back(std::move(accessor));
    return static_cast<int>(model_.accessors.size()) - 1;
  }

  void finish() {
    while (data_.size() % 4 != 0) data_.push_back(0);
    tinygltf::Buffer buffer;
    buffer.data = std::move(data_);
    model_.buffers.push_back(std::move(buffer));
  }

 private:
  tinygltf::Model& model_;
  std::vector<unsigned char> data_;
};

void check_glb_inputs(const BodyModel& model, const Vertices& rest, const GlbOptions& options) {
  if (rest.rows() != model.vertex_count())
    throw Error(ErrorKind::InvalidArgument,
                "glTF export: " + std::to_string(rest.rows()) + " vertices given, model '" + model.name() +
                    "' has " + std::to_string(model.vertex_count()),
                "vertices");
  if (!rest.allFinite())
    throw Error(ErrorKind::InvalidArgument, "glTF export: vertices contain NaN or infinity", "vertices");
  if (options.include_skin && model.joint_count() > 65536)  // JOINTS_0 is at most 16-bit
    throw Error(ErrorKind::Unsupported, "glTF export: more than 65536 joints", "joints");
  const auto& extra = options.extra_vertex_scalar;
  if (!extra.empty()) {
    if (extra.size() != static_cast<size_t>(rest.rows()))
      throw Error(ErrorKind::InvalidArgument,
                  "glTF export: extra_vertex_scalar has " + std::to_string(extra.size()) + " values for " +
                      std::to_string(rest.rows()) + " vertices",
                  "extra_vertex_scalar");
    for (float v : extra)
      if (!std::isfinite(v))
        throw Error(ErrorKind::InvalidArgument, "glTF export: extra_vertex_scalar contains NaN or infinity",
                    "extra_vertex_scalar");
  }
}

}  // namespace

namespace {

// The glTF document before its provenance: tinygltf's output, parsed back by write_glb.
std::string tinygltf_glb(const BodyModel& model, const Vertices& rest, const GlbOptions& options) {
  check_glb_inputs(model, rest, options);
  const auto& data = model.data();
  const int joint_count = model.joint_count();
  const UvSplitMesh& split = model.uv_split();
  const size_t n = split.source.size();  // vertices written
  auto src = [&](size_t v) { return static_cast<Eigen::Index>(split.source[v]); };

  tinygltf::Model gltf;
  gltf.asset.version = "2.0";
  gltf.asset.generator = std::string("Caliper ") + CALIPER_VERSION;
  BinaryBuilder bin(gltf);

  // Positions, with the min/max the spec requires, computed from the floats actually written.
  std::vector<float> positions(n * 3);
  std::vector<double> pmin(3, std::numeric_limits<double>::infinity()), pmax(3, -std::numeric_limits<double>::infinity());
  for (size_t v = 0; v < n; ++v)
    for (int c = 0; c < 3; ++c) {
      const float x = static_cast<float>(rest(src(v), c));
      positions[v * 3 + c] = x;
      pmin[c] = std::min(pmin[c], static_cast<double>(x));
      pmax[c] = std::max(pmax[c], static_cast<double>(x));
    }
  // Normals renormalised in float, so they are unit length to float precision.
  const Vertices normals_d = vertex_normals(rest, model.faces());
  std::vector<float> normals(n * 3);
  for (size_t v = 0; v < n; ++v) {
    float f[3];
    for (int c = 0; c < 3; ++c) f[c] = static_cast<float>(normals_d(src(v), c));
    const float len = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (int c = 0; c < 3; ++c) normals[v * 3 + c] = len > 0 ? f[c] / len : (c == 1 ? 1.0f : 0.0f);
  }

  tinygltf::Primitive primitive;
  primitive.mode = kTriangles;
  primitive.attributes["POSITION"] = bin.add_accessor(positions, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3,
                                                      n, kArrayBuffer, pmin, pmax);
  primitive.attributes["NORMAL"] =
      bin.add_accessor(normals, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n, kArrayBuffer);

  if (options.include_skin) {
    std::vector<float> weights(n * 4);
    std::vector<std::uint8_t> joints8;
    std::vector<std::uint16_t> joints16;
    const bool small = joint_count <= 256;
    if (small) joints8.resize(n * 4);
    else joints16.resize(n * 4);
    for (size_t v = 0; v < n; ++v) {
      const Influences inf = top_influences(data.skin_weights, src(v));
      for (int k = 0; k < 4; ++k) {
        weights[v * 4 + k] = inf.weights[k];
        if (small) joints8[v * 4 + k] = static_cast<std::uint8_t>(inf.joints[k]);
        else joints16[v * 4 + k] = static_cast<std::uint16_t>(inf.joints[k]);
      }
    }
    primitive.attributes["JOINTS_0"] =
        small ? bin.add_accessor(joints8, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, n, kArrayBuffer)
              : bin.add_accessor(joints16, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC4, n, kArrayBuffer);
    primitive.attributes["WEIGHTS_0"] =
        bin.add_accessor(weights, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, n, kArrayBuffer);
  }
  if (model.has_uvs()) {
    std::vector<float> texcoords(n * 2);
    for (size_t v = 0; v < n; ++v) {
      texcoords[v * 2] = static_cast<float>(split.uv[v][0]);
      texcoords[v * 2 + 1] = static_cast<float>(1.0 - split.uv[v][1]);  // glTF: v down from the top-left
    }
    primitive.attributes["TEXCOORD_0"] =
        bin.add_accessor(texcoords, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, n, kArrayBuffer);
  }
  if (!options.extra_vertex_scalar.empty()) {
    std::vector<float> extra(n);
    for (size_t v = 0; v < n; ++v) extra[v] = options.extra_vertex_scalar[split.source[v]];
    primitive.attributes["_UNCERTAINTY"] =
        bin.add_accessor(extra, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, n, kArrayBuffer);
  }
  // Morph targets: shape direction k as a POSITION displacement per written vertex, so weight w
  // moves the avatar by w standard deviations of β_k (the joints stay where they are).
  const int morphs = options.morphs ? model.shape_count() : 0;
  for (int k = 0; k < morphs; ++k) {
    std::vector<float> d(n * 3);
    std::vector<double> dmin(3, std::numeric_limits<double>::infinity()), dmax(3, -std::numeric_limits<double>::infinity());
    for (size_t v = 0; v < n; ++v)
      for (int c = 0; c < 3; ++c) {
        const float x = static_cast<float>(data.shape_directions(3 * src(v) + c, k));
        d[v * 3 + c] = x;
        dmin[c] = std::min(dmin[c], static_cast<double>(x));
        dmax[c] = std::max(dmax[c], static_cast<double>(x));
      }
    primitive.targets.push_back(
        {{"POSITION", bin.add_accessor(d, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n, kArrayBuffer, dmin, dmax)}});
  }

  // Indices: 16-bit when every index fits below 65535 (that value is the primitive-restart
  // sentinel, which glTF forbids as an index).
  const Faces& faces = split.faces;
  const size_t index_count = static_cast<size_t>(faces.size());
  if (n < 65535) {
    std::vector<std::uint16_t> idx(index_count);
    for (size_t i = 0; i < index_count; ++i) idx[i] = static_cast<std::uint16_t>(faces.data()[i]);
    primitive.indices = bin.add_accessor(idx, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR,
                                         index_count, kElementArrayBuffer);
  } else {
    std::vector<std::uint32_t> idx(index_count);
    for (size_t i = 0; i < index_count; ++i) idx[i] = static_cast<std::uint32_t>(faces.data()[i]);
    primitive.indices = bin.add_accessor(idx, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                                         index_count, kElementArrayBuffer);
  }

  tinygltf::Material material;
  material.name = "skin";
  material.pbrMetallicRoughness.baseColorFactor.assign(kSkinColour.begin(), kSkinColour.end());
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 0.7;  // matte, a soft highlight only
  gltf.materials.push_back(std::move(material));
  primitive.material = 0;

  tinygltf::Mesh mesh;
  mesh.name = options.mesh_name;
  mesh.primitives.push_back(std::move(primitive));
  mesh.weights.assign(static_cast<size_t>(morphs), 0.0);
  gltf.meshes.push_back(std::move(mesh));

  tinygltf::Scene scene;
  scene.name = "Caliper avatar";
  if (options.include_skin) {
    // Nodes 0..J−1: the model's joints in its order, node J: the root bone (export/rig.h). The
    // skin lists them in that order too, so JOINTS_0 holds the model's joint indices and the
    // root bone, which moves no vertex, comes last.
    const ExportRig rig = export_rig(model, model.joints(rest), rest, options.skeleton);
    for (int j = 0; j < rig.size(); ++j) {
      tinygltf::Node node;
      node.name = rig.names[static_cast<size_t>(j)];
      const Eigen::Vector3d t = rig.local_translation(j);
      const Eigen::Quaterniond q(rig.local_rotation(j));
      node.translation = {t.x(), t.y(), t.z()};
      if (!q.coeffs().isApprox(Eigen::Vector4d(0, 0, 0, 1), 1e-15)) node.rotation = {q.x(), q.y(), q.z(), q.w()};
      gltf.nodes.push_back(std::move(node));
    }
    for (int j = 0; j < rig.size(); ++j)
      if (const int p = rig.parents[static_cast<size_t>(j)]; p >= 0) gltf.nodes[static_cast<size_t>(p)].children.push_back(j);

    // Inverse bind matrices, column-major: the inverse of each joint's rest world transform
    // [R | x], i.e. [Rᵀ | −Rᵀx].
    std::vector<float> ibm(static_cast<size_t>(rig.size()) * 16, 0.0f);
    for (int j = 0; j < rig.size(); ++j) {
      const Eigen::Matrix3d rt = rig.orientations[static_cast<size_t>(j)].transpose();
      const Eigen::Vector3d t = -rt * rig.positions[static_cast<size_t>(j)];
      float* m = &ibm[static_cast<size_t>(j) * 16];
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) m[4 * c + r] = static_cast<float>(rt(r, c));
      for (int r = 0; r < 3; ++r) m[12 + r] = static_cast<float>(t(r));
      m[15] = 1.0f;
    }
    tinygltf::Skin skin;
    skin.name = "skeleton";
    skin.inverseBindMatrices = bin.add_accessor(ibm, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_MAT4,
                                                static_cast<size_t>(rig.size()), 0);
    skin.skeleton = rig.root;
    for (int j = 0; j < rig.size(); ++j) skin.joints.push_back(j);
    gltf.skins.push_back(std::move(skin));

    tinygltf::Node mesh_node;
    mesh_node.name = options.mesh_name;
    mesh_node.mesh = 0;
    mesh_node.skin = 0;
    gltf.nodes.push_back(std::move(mesh_node));
    tinygltf::Node armature;
    armature.name = "Armature";
    armature.children = {rig.root};
    gltf.nodes.push_back(std::move(armature));
    scene.nodes = {rig.size() + 1, rig.size()};
  } else {
    tinygltf::Node mesh_node;
    mesh_node.name = options.mesh_name;
    mesh_node.mesh = 0;
    gltf.nodes.push_back(std::move(mesh_node));
    scene.nodes = {0};
  }
  gltf.scenes.push_back(std::move(scene));
  gltf.defaultScene = 0;
  bin.finish();

  std::ostringstream out(std::ios::binary);
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&gltf, out, false, true) || !out)
    throw Error(ErrorKind::Io, "glTF export: the writer failed", "glb");
  return std::move(out).str();
}

// A GLB's JSON chunk as a document, and the GLB rebuilt around an edited one (the binary chunk
// kept byte for byte). Only used on tinygltf's own output, whose layout is known.
nlohmann::json glb_json(const std::string& glb) {
  std::uint32_t json_length = 0;
  std::memcpy(&json_length, glb.data() + 12, 4);
  return nlohmann::json::parse(glb.substr(20, json_length));
}

std::string with_glb_json(const std::string& glb, const nlohmann::json& doc) {
  std::uint32_t json_length = 0;
  std::memcpy(&json_length, glb.data() + 12, 4);
  const std::string bin = glb.substr(20 + json_length);
  std::string text = doc.dump();
  while (text.size() % 4 != 0) text += ' ';  // the spec pads the JSON chunk with spaces
  auto u32 = [](std::uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
  const auto total = static_cast<std::uint32_t>(12 + 8 + text.size() + bin.size());
  return "glTF" + u32(2) + u32(total) + u32(static_cast<std::uint32_t>(text.size())) + "JSON" + text + bin;
}

nlohmann::json provenance_json(const Provenance& p) {
  nlohmann::json measurements = nlohmann::json::object();
  for (const auto& m : measurements_in_edge_units(p)) measurements[m.name] = {{"value", m.value}, {"unit", m.unit}};
  return {{"body_model", p.body_model},
          {"model_source", p.model_source},
          {"licence", p.licence},
          {"commercial_use", p.commercial_use},
          {"sex", p.sex},
          {"regressor", p.regressor},
          {"measurements", measurements},
          {"caliper_version", p.caliper_version},
          {"units", "metres, +Y up, facing +Z"}};
}

// The GLB's document with the avatar's provenance in asset.copyright and asset.extras.caliper.
nlohmann::json document_with_provenance(const std::string& glb, const BodyModel& model, const ExportOptions& options) {
  const Provenance p = options.provenance.value_or(model_provenance(model));
  nlohmann::json doc = glb_json(glb);
  doc["asset"]["copyright"] = provenance_notice(p);
  doc["asset"]["extras"]["caliper"] = provenance_json(p);
  doc["asset"]["extras"]["caliper"]["skeleton"] = to_string(options.skeleton);
  if (options.morphs && model.shape_count() > 0) {  // names Blender and three.js show for the targets
    nlohmann::json names = nlohmann::json::array();
    for (int k = 0; k < model.shape_count(); ++k) names.push_back("shape_" + std::to_string(k));
    doc["meshes"][0]["extras"]["targetNames"] = names;
  }
  return doc;
}

}  // namespace

namespace {

// VRM 1.0's required humanoid bones (VRMC_vrm-1.0 humanoid.md).
constexpr const char* kVrmRequired[] = {"hips",         "spine",        "head",          "leftUpperLeg",
                                        "leftLowerLeg", "leftFoot",     "rightUpperLeg", "rightLowerLeg",
                                        "rightFoot",    "leftUpperArm", "leftLowerArm",  "leftHand",
                                        "rightUpperArm", "rightLowerArm", "rightHand"};

// The point between the eyes, estimated from the mesh: at the head joint's x, at 93.3 % of the
// standing height (eye height over stature in adult anthropometric surveys), 1 cm behind the
// frontmost surface of the face at that height.
Eigen::Vector3d estimated_eye_point(const Vertices& rest, const Eigen::Vector3d& head) {
  const double floor = rest.col(1).minCoeff(), crown = rest.col(1).maxCoeff();
  const double eye_y = floor + 0.933 * (crown - floor);
  double front = head.z();
  for (Eigen::Index v = 0; v < rest.rows(); ++v)
    if (std::abs(rest(v, 1) - eye_y) < 0.02 && std::abs(rest(v, 0) - head.x()) < 0.08) front = std::max(front, rest(v, 2));
  return {head.x(), eye_y, std::max(head.z(), front - 0.01)};
}

nlohmann::json vrm_meta(const Provenance& p) {
  nlohmann::json meta = {
      {"name", "Caliper avatar (" + p.body_model + ")"},
      {"version", p.caliper_version},
      {"authors", {"Caliper " + p.caliper_version}},
      {"copyrightInformation", provenance_notice(p)},
      {"thirdPartyLicenses", "Body model " + p.body_model + ": " + p.licence + (p.model_source.empty() ? "" : "; source: " + p.model_source)},
      {"licenseUrl", "https://vrm.dev/licenses/1.0/"},
      {"avatarPermission", "everyone"},
      {"allowExcessivelyViolentUsage", false},
      {"allowExcessivelySexualUsage", false},
      {"allowPoliticalOrReligiousUsage", false},
      {"allowAntisocialOrHateUsage", false},
      {"creditNotation", "unnecessary"},
      // A licence that forbids commercial use forbids it for the avatar too, and its body model's
      // terms (SMPL: no redistribution) travel with it.
      {"commercialUsage", p.commercial_use ? "corporation" : "personalNonProfit"},
      {"allowRedistribution", p.commercial_use},
      {"modification", p.commercial_use ? "allowModificationRedistribution" : "allowModification"}};
  if (!p.measurements.empty()) meta["references"] = {"measurements: " + measurements_text(p)};
  return meta;
}

}  // namespace

std::string write_vrm(const BodyModel& model, const Vertices& rest, const GlbOptions& options) {
  GlbOptions skinned = options;
  skinned.include_skin = true;
  const std::string glb = tinygltf_glb(model, rest, skinned);
  nlohmann::json doc = document_with_provenance(glb, model, skinned);
  const ExportRig rig = export_rig(model, model.joints(rest), rest, skinned.skeleton);
  nlohmann::json bones = nlohmann::json::object();
  int head = -1;
  for (int j = 0; j < model.joint_count(); ++j) {  // node j is model joint j (tinygltf_glb)
    const HumanoidBone* b = find_humanoid_bone(rig.model_names[static_cast<size_t>(j)]);
    if (b && *b->vrm) bones[b->vrm] = {{"node", j}};
    if (b && std::string(b->vrm) == "head") head = j;
  }
  for (const char* required : kVrmRequired)
    if (!bones.contains(required))
      throw Error(ErrorKind::Unsupported,
                  "VRM export: model '" + model.name() + "' has no joint for VRM's required bone '" + required +
                      "' (VRM needs SMPL's joint names)",
                  required);
  const Eigen::Vector3d head_at = rig.positions[static_cast<size_t>(head)];
  const Eigen::Vector3d offset =
      rig.orientations[static_cast<size_t>(head)].transpose() * (estimated_eye_point(rest, head_at) - head_at);
  const Provenance p = skinned.provenance.value_or(model_provenance(model));
  doc["extensionsUsed"].push_back("VRMC_vrm");
  doc["extensions"]["VRMC_vrm"] = {
      {"specVersion", "1.0"},
      {"meta", vrm_meta(p)},
      {"humanoid", {{"humanBones", bones}}},
      {"expressions", {{"preset", nlohmann::json::object()}, {"custom", nlohmann::json::object()}}},  // none: a plain body
      {"firstPerson", {{"meshAnnotations", {{{"node", rig.size()}, {"type", "auto"}}}}}},  // node J+1: the mesh
      {"lookAt", {{"offsetFromHeadBone", {offset.x(), offset.y(), offset.z()}}, {"type", "bone"}}}};
  return with_glb_json(glb, doc);
}

void save_vrm(const std::string& path, const BodyModel& model, const Vertices& rest, const GlbOptions& options) {
  write_file(path, write_vrm(model, rest, options));
}

std::string write_glb(const BodyModel& model, const Vertices& rest, const GlbOptions& options) {
  const std::string glb = tinygltf_glb(model, rest, options);
  return with_glb_json(glb, document_with_provenance(glb, model, options));
}

namespace {

// Shortest decimal that reads back to the same double: exact OBJ round trips, locale-free.
void append_number(std::string& out, double value) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, value);
  out.append(buf, r.ptr);
}

}  // namespace

void save_glb(const std::string& path, const BodyModel& model, const Vertices& rest, const GlbOptions& options) {
  write_file(path, write_glb(model, rest, options));
}

// ---- Wavefront OBJ ---------------------------------------------------------------------------

void save_obj(const std::string& path, const Vertices& vertices, const Faces& faces, const UvCoordinates& uv,
              const Faces& uv_faces, const std::string& comment) {
  write_file(path, write_obj(vertices, faces, uv, uv_faces, comment));
}

std::string write_obj(const Vertices& vertices, const Faces& faces, const std::string& comment) {
  return write_obj(vertices, faces, UvCoordinates(), Faces(), comment);
}

std::string write_obj(const Vertices& vertices, const Faces& faces, const UvCoordinates& uv, const Faces& uv_faces,
                      const std::string& comment) {
  const bool textured = uv_faces.rows() > 0;
  if (textured && uv_faces.rows() != faces.rows())
    throw Error(ErrorKind::InvalidArgument,
                "OBJ export: " + std::to_string(uv_faces.rows()) + " UV faces for " + std::to_string(faces.rows()) + " faces",
                "uv_faces");
  if (textured && (uv_faces.minCoeff() < 0 || uv_faces.maxCoeff() >= uv.rows()))
    throw Error(ErrorKind::InvalidArgument, "OBJ export: UV index out of range [0, " + std::to_string(uv.rows()) + ")",
                "uv_faces");
  if (!uv.allFinite()) throw Error(ErrorKind::InvalidArgument, "OBJ export: UVs contain NaN or infinity", "uv_coordinates");
  if (!vertices.allFinite())
    throw Error(ErrorKind::InvalidArgument, "OBJ export: vertices contain NaN or infinity", "vertices");
  if (faces.size() > 0 && (faces.minCoeff() < 0 || faces.maxCoeff() >= vertices.rows()))
    throw Error(ErrorKind::InvalidArgument,
                "OBJ export: face index out of range [0, " + std::to_string(vertices.rows()) + ")", "faces");
  std::string out;
  out.reserve(static_cast<size_t>(vertices.rows()) * 80 + static_cast<size_t>(faces.rows()) * 40 + 256);
  std::string_view rest = comment;
  while (!rest.empty()) {  // every comment line gets its own '#'
    const size_t eol = rest.find('\n');
    out += "# ";
    out += rest.substr(0, eol);
    out += '\n';
    rest = eol == std::string_view::npos ? std::string_view{} : rest.substr(eol + 1);
  }
  out += std::string("# Caliper ") + CALIPER_VERSION + ", " + std::to_string(vertices.rows()) + " vertices, " +
         std::to_string(faces.rows()) + " triangles, metres, +Y up, +Z forward\n";
  const Vertices normals = vertex_normals(vertices, faces);
  for (Eigen::Index v = 0; v < vertices.rows(); ++v) {
    out += 'v';
    for (int c = 0; c < 3; ++c) { out += ' '; append_number(out, vertices(v, c)); }
    out += '\n';
  }
  for (Eigen::Index v = 0; v < normals.rows(); ++v) {
    out += "vn";
    for (int c = 0; c < 3; ++c) { out += ' '; append_number(out, normals(v, c)); }
    out += '\n';
  }
  if (textured)
    for (Eigen::Index t = 0; t < uv.rows(); ++t) {
      out += "vt";
      for (int c = 0; c < 2; ++c) { out += ' '; append_number(out, uv(t, c)); }
      out += '\n';
    }
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    out += 'f';
    for (int c = 0; c < 3; ++c) {
      const std::string i = std::to_string(faces(f, c) + 1);  // OBJ is 1-based
      out += ' ';
      out += i;
      out += '/';
      if (textured) out += std::to_string(uv_faces(f, c) + 1);
      out += '/';
      out += i;
    }
    out += '\n';
  }
  return out;
}

namespace {

class ObjParser {
 public:
  explicit ObjParser(std::string path) : path_(std::move(path)) {}

  TexturedMesh parse(std::string_view text) {
    size_t pos = 0;
    while (pos < text.size()) {
      size_t eol = text.find('\n', pos);
      if (eol == std::string_view::npos) eol = text.size();
      std::string_view line = text.substr(pos, eol - pos);
      pos = eol + 1;
      ++line_no_;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      // A trailing backslash continues the statement on the next line.
      if (!line.empty() && line.back() == '\\') {
        std::string joined(line.substr(0, line.size() - 1));
        const int first_line = line_no_;
        while (pos < text.size()) {
          size_t e = text.find('\n', pos);
          if (e == std::string_view::npos) e = text.size();
          std::string_view next = text.substr(pos, e - pos);
          pos = e + 1;
          ++line_no_;
          if (!next.empty() && next.back() == '\r') next.remove_suffix(1);
          const bool more = !next.empty() && next.back() == '\\';
          joined += ' ';
          joined += more ? next.substr(0, next.size() - 1) : next;
          if (!more) break;
        }
        const int last_line = line_no_;
        line_no_ = first_line;  // report errors at the statement's first line
        statement(joined);
        line_no_ = last_line;
      } else {
        statement(line);
      }
    }
    return finish();
  }

 private:
  struct Corner {
    std::int64_t v, vt, vn;  // 0-based, −1 = absent
  };
  struct PendingFace {
    std::vector<Corner> corners;
    int line;
  };

  [[noreturn]] void fail(const std::string& what, int line = -1) const {
    throw Error(ErrorKind::Format, path_ + ":" + std::to_string(line < 0 ? line_no_ : line) + ": " + what, path_);
  }

  static std::string_view next_token(std::string_view& s) {
    size_t b = 0;
    while (b < s.size() && (s[b] == ' ' || s[b] == '\t')) ++b;
    size_t e = b;
    while (e < s.size() && s[e] != ' ' && s[e] != '\t') ++e;
    std::string_view token = s.substr(b, e - b);
    s.remove_prefix(e);
    return token;
  }

  double parse_double(std::string_view token) const {
    // from_chars rejects a leading '+', which some exporters write.
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    double value = 0;
    const auto r = std::from_chars(token.data(), token.data() + token.size(), value);
    if (r.ec != std::errc() || r.ptr != token.data() + token.size() || !std::isfinite(value))
      fail("malformed number '" + std::string(token) + "'");
    return value;
  }

  // A 1-based or negative (relative) OBJ index resolved to 0-based; positive indices are checked
  // against the final counts in finish(), so files that list faces before vertices still load.
  std::int64_t parse_index(std::string_view token, std::int64_t count_so_far, const char* what) const {
    std::int64_t value = 0;
    const auto r = std::from_chars(token.data(), token.data() + token.size(), value);
    if (token.empty() || r.ec != std::errc() || r.ptr != token.data() + token.size())
      fail(std::string("malformed ") + what + " index '" + std::string(token) + "'");
    if (value == 0) fail(std::string(what) + " index 0 (OBJ indices start at 1)");
    if (value < 0) {
      if (-value > count_so_far)
        fail(std::string(what) + " index " + std::to_string(value) + " out of range: only " +
             std::to_string(count_so_far) + " defined so far");
      return count_so_far + value;
    }
    return value - 1;
  }

  void statement(std::string_view line) {
    if (const size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    std::string_view rest = line;
    const std::string_view keyword = next_token(rest);
    if (keyword.empty()) return;
    if (keyword == "v") {
      std::array<double, 3> xyz{};
      int k = 0;
      for (std::string_view t = next_token(rest); !t.empty(); t = next_token(rest), ++k) {
        const double value = parse_double(t);
        if (k < 3) xyz[static_cast<size_t>(k)] = value;
      }
      // x y z, optionally w or an r g b colour: accept 3, 4 or 6 numbers.
      if (k != 3 && k != 4 && k != 6) fail("vertex needs 3 coordinates, has " + std::to_string(k));
      positions_.push_back(xyz);
    } else if (keyword == "vt" || keyword == "vn") {
      int k = 0;
      std::array<double, 2> st{};
      for (std::string_view t = next_token(rest); !t.empty(); t = next_token(rest), ++k) {
        const double value = parse_double(t);
        if (k < 2) st[static_cast<size_t>(k)] = value;
      }
      if (keyword == "vt") texcoords_.push_back(st);
      if (keyword == "vn" && k != 3) fail("normal needs 3 numbers, has " + std::to_string(k));
      if (keyword == "vt" && (k < 1 || k > 3)) fail("texture coordinate needs 1 to 3 numbers, has " + std::to_string(k));
      ++(keyword == "vn" ? normal_count_ : texcoord_count_);
    } else if (keyword == "f") {
      PendingFace face{{}, line_no_};
      for (std::string_view t = next_token(rest); !t.empty(); t = next_token(rest)) {
        std::array<std::string_view, 3> parts{};
        size_t slash1 = t.find('/');
        parts[0] = t.substr(0, slash1);
        if (slash1 != std::string_view::npos) {
          std::string_view tail = t.substr(slash1 + 1);
          const size_t slash2 = tail.find('/');
          parts[1] = tail.substr(0, slash2);
          if (slash2 != std::string_view::npos) parts[2] = tail.substr(slash2 + 1);
          if (slash2 == std::string_view::npos && tail.empty()) fail("malformed face corner '" + std::string(t) + "'");
        }
        Corner c{parse_index(parts[0], static_cast<std::int64_t>(positions_.size()), "vertex"), -1, -1};
        if (!parts[1].empty()) c.vt = parse_index(parts[1], texcoord_count_, "texture coordinate");
        if (!parts[2].empty()) c.vn = parse_index(parts[2], normal_count_, "normal");
        face.corners.push_back(c);
      }
      if (face.corners.size() < 3) fail("face needs at least 3 vertices, has " + std::to_string(face.corners.size()));
      faces_.push_back(std::move(face));
    }
    // Other statements (o, g, s, usemtl, mtllib, l, p, vp, …) carry nothing a body mesh needs.
  }

  TexturedMesh finish() {
    if (faces_.empty()) fail("no faces", line_no_);
    const auto nv = static_cast<std::int64_t>(positions_.size());
    if (nv > std::numeric_limits<std::int32_t>::max()) fail("too many vertices", line_no_);
    size_t triangles = 0;
    for (const auto& f : faces_) {
      for (const Corner& c : f.corners) {
        if (c.v >= nv)
          fail("vertex index " + std::to_string(c.v + 1) + " out of range: the file has " + std::to_string(nv) +
                   " vertices", f.line);
        if (c.vt >= texcoord_count_)
          fail("texture coordinate index " + std::to_string(c.vt + 1) + " out of range", f.line);
        if (c.vn >= normal_count_) fail("normal index " + std::to_string(c.vn + 1) + " out of range", f.line);
      }
      triangles += f.corners.size() - 2;
    }
    TexturedMesh out;
    Mesh& mesh = out.mesh;
    mesh.vertices.resize(nv, 3);
    for (std::int64_t v = 0; v < nv; ++v)
      for (int c = 0; c < 3; ++c) mesh.vertices(v, c) = positions_[static_cast<size_t>(v)][static_cast<size_t>(c)];
    mesh.faces.resize(static_cast<Eigen::Index>(triangles), 3);
    Eigen::Index t = 0;
    for (const auto& f : faces_)  // fan from the first corner: exact for the convex polygons OBJ stores
      for (size_t k = 1; k + 1 < f.corners.size(); ++k, ++t)
        mesh.faces.row(t) << static_cast<std::int32_t>(f.corners[0].v), static_cast<std::int32_t>(f.corners[k].v),
            static_cast<std::int32_t>(f.corners[k + 1].v);
    // Texture coordinates only when every corner has one (the same fan as the faces).
    bool every_corner = true;
    for (const auto& f : faces_)
      for (const Corner& c : f.corners) every_corner = every_corner && c.vt >= 0;
    if (every_corner && !texcoords_.empty()) {
      out.uv_coordinates.resize(static_cast<Eigen::Index>(texcoords_.size()), 2);
      for (size_t i = 0; i < texcoords_.size(); ++i)
        out.uv_coordinates.row(static_cast<Eigen::Index>(i)) << texcoords_[i][0], texcoords_[i][1];
      out.uv_faces.resize(static_cast<Eigen::Index>(triangles), 3);
      t = 0;
      for (const auto& f : faces_)
        for (size_t k = 1; k + 1 < f.corners.size(); ++k, ++t)
          out.uv_faces.row(t) << static_cast<std::int32_t>(f.corners[0].vt), static_cast<std::int32_t>(f.corners[k].vt),
              static_cast<std::int32_t>(f.corners[k + 1].vt);
    }
    return out;
  }

  std::string path_;
  int line_no_ = 0;
  std::vector<std::array<double, 3>> positions_;
  std::int64_t texcoord_count_ = 0;
  std::vector<std::array<double, 2>> texcoords_;
  std::int64_t normal_count_ = 0;
  std::vector<PendingFace> faces_;
};

}  // namespace

Mesh read_obj(const std::string& path) { return read_obj_textured(path).mesh; }

TexturedMesh read_obj_textured(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw Error(ErrorKind::Io, "'" + path + "' is a directory", path);
  std::ifstream file(path, std::ios::binary);
  if (!file) throw Error(ErrorKind::Io, "cannot open '" + path + "'", path);
  std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (file.bad()) throw Error(ErrorKind::Io, "cannot read '" + path + "'", path);
  return ObjParser(path).parse(text);
}

}  // namespace caliper
