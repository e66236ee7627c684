// Tests for the glTF (.glb) and OBJ export: a hand-built 26-vertex body with SMPL's 24 joints,
// checked by decoding the GLB ourselves, by Assimp, and by the Khronos glTF validator.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "caliper/body/body_model.h"
#include "caliper/body/mesh.h"
#include "caliper/errors.h"
#include "caliper/measure/geometry.h"
#include "caliper/export/fbx.h"
#include "caliper/export/gltf.h"
#include "fixtures.h"

#ifdef CALIPER_HAVE_ASSIMP
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#endif

namespace fs = std::filesystem;
using caliper::BodyModel;
using caliper::BodyModelData;
using caliper::Error;
using caliper::ErrorKind;
using caliper::Faces;
using caliper::Vertices;
using caliper::signed_volume;
using nlohmann::json;

using caliper::test::catch_error;

namespace {

// A closed square tube standing on the floor: 6 rings of 4 vertices (vertex 1 + 4r + k) and a
// cap centre at each end (vertex 0 at the bottom, 25 at the top). 26 vertices, 48 triangles.
constexpr int kRings = 6;
constexpr int kVertices = 2 + 4 * kRings;

Vertices tube_vertices() {
  Vertices v(kVertices, 3);
  v.row(0) << 0, 0, 0;
  const double xz[4][2] = {{0.2, 0.1}, {-0.2, 0.1}, {-0.2, -0.1}, {0.2, -0.1}};  // counter-clockwise seen from above
  for (int r = 0; r < kRings; ++r)
    for (int k = 0; k < 4; ++k) v.row(1 + 4 * r + k) << xz[k][0], 0.1 + 0.3 * r, xz[k][1];
  v.row(kVertices - 1) << 0, 1.7, 0;
  return v;
}

Faces tube_faces() {
  std::vector<std::array<int, 3>> f;
  auto ring = [](int r, int k) { return 1 + 4 * r + (k % 4); };
  for (int k = 0; k < 4; ++k) f.push_back({0, ring(0, k), ring(0, k + 1)});
  for (int r = 0; r + 1 < kRings; ++r)
    for (int k = 0; k < 4; ++k) {
      f.push_back({ring(r, k), ring(r + 1, k), ring(r + 1, k + 1)});
      f.push_back({ring(r, k), ring(r + 1, k + 1), ring(r, k + 1)});
    }
  for (int k = 0; k < 4; ++k) f.push_back({kVertices - 1, ring(kRings - 1, k + 1), ring(kRings - 1, k)});
  Faces faces(static_cast<Eigen::Index>(f.size()), 3);
  for (size_t i = 0; i < f.size(); ++i) faces.row(static_cast<Eigen::Index>(i)) << f[i][0], f[i][1], f[i][2];
  return faces;
}

// Skin weights (hand-picked so the top-4 choice is known):
//   vertex 0: joint 0 only;
//   vertex 1: joints 1..6 = .05 .30 .10 .25 .20 .10 → keeps 2, 4, 5 and 3 (tie with 6: lower index);
//   vertex 2: joints 23 and 22 at .5 each;  vertex 3: joints 7, 8, 9 at 1/3 each;
//   others:   joint v mod 24 at .7, joint (v+5) mod 24 at .3.
// Nonzero influences written: 1 + 4 + 2 + 3 + 2·22 = 54.
constexpr int kInfluencesWritten = 54;

BodyModelData tube_data() {
  BodyModelData d;
  d.name = "tube";
  d.template_vertices = tube_vertices();
  d.faces = tube_faces();
  d.shape_directions = Eigen::MatrixXd::Zero(3 * kVertices, 2);
  for (int v = 0; v < kVertices; ++v) d.shape_directions(3 * v + 1, 0) = 0.01 * d.template_vertices(v, 1);  // taller
  d.shape_directions(3 * 5 + 0, 1) = 0.02;
  d.joint_names = caliper::smpl_joint_names();
  d.parents = caliper::smpl_parents();
  // Joint j sits on vertex 1 + j (j < 22); joints 22 and 23 midway between vertices 23 and 24.
  std::vector<Eigen::Triplet<double>> reg;
  for (int j = 0; j < 22; ++j) reg.emplace_back(j, 1 + j, 1.0);
  for (int j = 22; j < 24; ++j) { reg.emplace_back(j, 23, 0.5); reg.emplace_back(j, 24, 0.5); }
  d.joint_regressor.resize(24, kVertices);
  d.joint_regressor.setFromTriplets(reg.begin(), reg.end());
  std::vector<Eigen::Triplet<double>> w;
  w.emplace_back(0, 0, 1.0);
  const double v1[6] = {0.05, 0.30, 0.10, 0.25, 0.20, 0.10};
  for (int j = 0; j < 6; ++j) w.emplace_back(1, 1 + j, v1[j]);
  w.emplace_back(2, 23, 0.5);
  w.emplace_back(2, 22, 0.5);
  for (int j = 7; j <= 9; ++j) w.emplace_back(3, j, 1.0 / 3);
  for (int v = 4; v < kVertices; ++v) { w.emplace_back(v, v % 24, 0.7); w.emplace_back(v, (v + 5) % 24, 0.3); }
  d.skin_weights.resize(kVertices, 24);
  d.skin_weights.setFromTriplets(w.begin(), w.end());
  return d;
}

const BodyModel& tube() {
  static const BodyModel model(tube_data());
  return model;
}

// ---- a minimal GLB decoder, independent of tinygltf -------------------------------------------

std::uint32_t u32(const std::string& s, size_t at) {
  std::uint32_t x;
  std::memcpy(&x, s.data() + at, 4);
  return x;
}

struct Glb {
  json doc;
  std::string bin;

  // Accessor values as doubles, count × components, tightly packed views only (what we write).
  std::vector<double> read(int accessor) const {
    const json& a = doc["accessors"][accessor];
    const json& view = doc["bufferViews"][a["bufferView"].get<int>()];
    const int ct = a["componentType"];
    static const std::map<std::string, int> comps = {{"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}, {"MAT4", 16}};
    const size_t n = a["count"].get<size_t>() * static_cast<size_t>(comps.at(a["type"]));
    const size_t size = ct == 5126 || ct == 5125 ? 4 : ct == 5123 ? 2 : 1;
    EXPECT_FALSE(view.contains("byteStride"));
    const size_t start = view.value("byteOffset", size_t{0}) + a.value("byteOffset", size_t{0});
    EXPECT_LE(start + n * size, bin.size());
    EXPECT_LE(n * size, view["byteLength"].get<size_t>());
    std::vector<double> out(n);
    for (size_t i = 0; i < n; ++i) {
      const char* p = bin.data() + start + i * size;
      if (ct == 5126) { float f; std::memcpy(&f, p, 4); out[i] = f; }
      else if (ct == 5125) { std::uint32_t x; std::memcpy(&x, p, 4); out[i] = x; }
      else if (ct == 5123) { std::uint16_t x; std::memcpy(&x, p, 2); out[i] = x; }
      else if (ct == 5121) { out[i] = static_cast<unsigned char>(*p); }
      else ADD_FAILURE() << "unexpected componentType " << ct;
    }
    return out;
  }
  std::vector<float> read_floats(int accessor) const {
    const std::vector<double> d = read(accessor);
    return std::vector<float>(d.begin(), d.end());
  }
  int attribute(const std::string& name) const { return doc["meshes"][0]["primitives"][0]["attributes"].value(name, -1); }
};

Glb parse_glb(const std::string& bytes) {
  Glb g;
  if (bytes.size() < 28) { ADD_FAILURE() << "GLB too short"; return g; }
  EXPECT_EQ(bytes.substr(0, 4), "glTF");
  EXPECT_EQ(u32(bytes, 4), 2u);
  EXPECT_EQ(u32(bytes, 8), bytes.size());
  const std::uint32_t json_len = u32(bytes, 12);
  EXPECT_EQ(u32(bytes, 16), 0x4E4F534Au);  // "JSON"
  EXPECT_EQ(json_len % 4, 0u);
  g.doc = json::parse(bytes.substr(20, json_len));
  const size_t bin_at = 20 + json_len;
  EXPECT_LE(bin_at + 8, bytes.size());
  if (bin_at + 8 > bytes.size()) return g;
  const std::uint32_t bin_len = u32(bytes, bin_at);
  EXPECT_EQ(u32(bytes, bin_at + 4), 0x004E4942u);  // "BIN\0"
  EXPECT_EQ(bin_len % 4, 0u);
  EXPECT_EQ(bin_at + 8 + bin_len, bytes.size());  // exactly two chunks
  g.bin = bytes.substr(bin_at + 8, bin_len);
  EXPECT_EQ(g.doc["buffers"].size(), 1u);
  EXPECT_EQ(g.doc["buffers"][0]["byteLength"].get<size_t>(), bin_len);
  EXPECT_FALSE(g.doc["buffers"][0].contains("uri"));
  return g;
}

fs::path temp_dir() {
  const fs::path dir = fs::temp_directory_path() /
                       ("caliper-export-test-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                        "-" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::create_directories(dir);
  return dir;
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

}  // namespace

// ---- the fixture itself -----------------------------------------------------------------------

TEST(ExportFixture, TubeIsAClosedOutwardBody) {
  const auto check = caliper::check_mesh(tube_faces(), kVertices);
  EXPECT_TRUE(check.closed);
  EXPECT_TRUE(check.consistently_oriented);
  EXPECT_NEAR(signed_volume(tube_vertices(), tube_faces()), 0.4 * 0.2 * 1.5 + 2 * (0.4 * 0.2 * 0.1 / 3), 1e-12);
}

// ---- GLB structure ----------------------------------------------------------------------------

TEST(Glb, HeaderChunksAndCounts) {
  const Vertices rest = tube().rest_vertices(Eigen::Vector2d(1.0, -0.5));
  const Glb g = parse_glb(caliper::write_glb(tube(), rest));
  const json& d = g.doc;
  EXPECT_EQ(d["asset"]["version"], "2.0");
  EXPECT_EQ(d["asset"]["generator"].get<std::string>().rfind("Caliper ", 0), 0u);
  ASSERT_EQ(d["meshes"].size(), 1u);
  ASSERT_EQ(d["meshes"][0]["primitives"].size(), 1u);
  ASSERT_EQ(d["skins"].size(), 1u);
  EXPECT_EQ(d["nodes"].size(), 24u + 1u + 2u);  // joints, the root bone, the mesh, the Armature
  EXPECT_EQ(d["meshes"][0]["name"], "avatar");
  const json& prim = d["meshes"][0]["primitives"][0];
  EXPECT_EQ(prim.value("mode", 4), 4);
  EXPECT_EQ(d["accessors"][g.attribute("POSITION")]["count"], kVertices);
  EXPECT_EQ(d["accessors"][prim["indices"].get<int>()]["count"], 3 * tube().face_count());
  EXPECT_EQ(g.attribute("_UNCERTAINTY"), -1);
  ASSERT_EQ(d["materials"].size(), 1u);
  EXPECT_EQ(d["materials"][0]["pbrMetallicRoughness"]["metallicFactor"], 0.0);
}

TEST(Glb, PositionsNormalsAndIndicesMatchTheMesh) {
  const Vertices rest = tube().rest_vertices(Eigen::Vector2d(1.0, -0.5));
  const Glb g = parse_glb(caliper::write_glb(tube(), rest));
  const int pos_acc = g.attribute("POSITION");
  const std::vector<double> p = g.read(pos_acc);
  ASSERT_EQ(p.size(), 3u * kVertices);
  for (int v = 0; v < kVertices; ++v)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(p[3 * v + c], static_cast<float>(rest(v, c)));
  // min/max: the tube spans x ±0.2, z ±0.1, y from 0 to 1.7·1.01 (shape 0 stretches heights by 1 %).
  const json& acc = g.doc["accessors"][pos_acc];
  EXPECT_EQ(acc["min"][0].get<double>(), static_cast<float>(-0.2));
  EXPECT_EQ(acc["max"][2].get<double>(), static_cast<float>(0.1));
  EXPECT_EQ(acc["min"][1].get<double>(), 0.0);
  EXPECT_EQ(acc["max"][1].get<double>(), static_cast<float>(1.7 * 1.01));
  const std::vector<float> n = g.read_floats(g.attribute("NORMAL"));
  ASSERT_EQ(n.size(), 3u * kVertices);
  for (int v = 0; v < kVertices; ++v)
    EXPECT_NEAR(std::sqrt(n[3 * v] * n[3 * v] + n[3 * v + 1] * n[3 * v + 1] + n[3 * v + 2] * n[3 * v + 2]), 1.0, 1e-6);
  // The bottom cap centre faces down, the top one up.
  EXPECT_NEAR(n[1], -1.0, 1e-6);
  EXPECT_NEAR(n[3 * (kVertices - 1) + 1], 1.0, 1e-6);
  const std::vector<double> idx = g.read(g.doc["meshes"][0]["primitives"][0]["indices"].get<int>());
  const Faces& f = tube().faces();
  ASSERT_EQ(idx.size(), static_cast<size_t>(f.size()));
  for (Eigen::Index t = 0; t < f.rows(); ++t)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(idx[static_cast<size_t>(3 * t + c)], f(t, c));
}

// A node's rest world transform, composed from the document's TRS chain (independent of the
// writer's rig code).
Eigen::Affine3d node_world(const json& nodes, const std::vector<int>& parent_of, int node) {
  Eigen::Affine3d local = Eigen::Affine3d::Identity();
  const json& n = nodes[node];
  if (n.contains("translation")) {
    const auto t = n["translation"].get<std::vector<double>>();
    local.translate(Eigen::Vector3d(t[0], t[1], t[2]));
  }
  if (n.contains("rotation")) {
    const auto q = n["rotation"].get<std::vector<double>>();
    local.rotate(Eigen::Quaterniond(q[3], q[0], q[1], q[2]));
  }
  const int p = parent_of[static_cast<size_t>(node)];
  return p < 0 ? local : node_world(nodes, parent_of, p) * local;
}

std::vector<int> node_parents(const json& nodes) {
  std::vector<int> parent_of(nodes.size(), -1);
  for (size_t i = 0; i < nodes.size(); ++i)
    for (int c : nodes[i].value("children", std::vector<int>{})) {
      EXPECT_EQ(parent_of[static_cast<size_t>(c)], -1) << "node with two parents";
      parent_of[static_cast<size_t>(c)] = static_cast<int>(i);
    }
  return parent_of;
}

TEST(Glb, JointHierarchyRestTransformsAndInverseBindMatrices) {
  const Vertices rest = tube().rest_vertices(Eigen::Vector2d(0.5, 2.0));
  const Glb g = parse_glb(caliper::write_glb(tube(), rest));
  const json& nodes = g.doc["nodes"];
  const auto& names = caliper::smpl_joint_names();
  const auto& parents = caliper::smpl_parents();
  // Expected joint positions straight from the regressor's definition (vertex 1 + j, or a midpoint).
  auto joint = [&](int j) -> Eigen::Vector3d {
    return j < 22 ? Eigen::Vector3d(rest.row(1 + j).transpose()) : Eigen::Vector3d(0.5 * (rest.row(23) + rest.row(24)).transpose());
  };
  const json& skin = g.doc["skins"][0];
  ASSERT_EQ(skin["joints"].size(), 25u);  // SMPL's 24 in SMPL's order, then the root bone
  const int root = skin["skeleton"];
  EXPECT_EQ(skin["joints"][24].get<int>(), root);
  EXPECT_EQ(nodes[root]["name"], "root");
  const std::vector<int> parent_of = node_parents(nodes);
  const std::vector<double> ibm = g.read(skin["inverseBindMatrices"].get<int>());
  ASSERT_EQ(ibm.size(), 25u * 16u);
  // The root bone stands on the floor (the lowest vertex, y = 0 here) under the pelvis.
  const Eigen::Affine3d root_world = node_world(nodes, parent_of, root);
  EXPECT_NEAR(root_world.translation().x(), joint(0).x(), 1e-9);
  EXPECT_NEAR(root_world.translation().y(), rest.col(1).minCoeff(), 1e-9);
  EXPECT_NEAR(root_world.translation().z(), joint(0).z(), 1e-9);
  const int arm = parent_of[static_cast<size_t>(root)];
  ASSERT_GE(arm, 0);
  EXPECT_EQ(nodes[arm]["name"], "Armature");
  EXPECT_FALSE(nodes[arm].contains("translation"));
  EXPECT_EQ(parent_of[static_cast<size_t>(arm)], -1);
  for (int j = 0; j < 25; ++j) {
    const int node = skin["joints"][j];
    const Eigen::Affine3d world = node_world(nodes, parent_of, node);
    if (j < 24) {
      EXPECT_EQ(nodes[node]["name"], names[j]);
      EXPECT_FALSE(nodes[node].contains("mesh"));
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(world.translation()(c), joint(j)(c), 1e-9) << names[j];
      const int expected_parent = parents[j] < 0 ? root : skin["joints"][parents[j]].get<int>();
      EXPECT_EQ(parent_of[static_cast<size_t>(node)], expected_parent) << names[j];
    }
    // A pure rotation, no scale.
    EXPECT_TRUE((world.linear().transpose() * world.linear()).isIdentity(1e-9)) << j;
    EXPECT_NEAR(world.linear().determinant(), 1.0, 1e-9) << j;
    // IBM = the inverse of the joint's rest world transform, column-major.
    const Eigen::Matrix4d want = world.inverse().matrix();
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) EXPECT_NEAR(ibm[static_cast<size_t>(16 * j + 4 * c + r)], want(r, c), 1e-6) << j << " " << r << "," << c;
  }
  // The skinned mesh node is a scene root with no transform and no children.
  int mesh_node = -1;
  for (size_t i = 0; i < nodes.size(); ++i)
    if (nodes[i].contains("mesh")) mesh_node = static_cast<int>(i);
  ASSERT_GE(mesh_node, 0);
  EXPECT_EQ(nodes[mesh_node]["skin"], 0);
  EXPECT_EQ(parent_of[static_cast<size_t>(mesh_node)], -1);
  EXPECT_FALSE(nodes[mesh_node].contains("translation"));
  EXPECT_FALSE(nodes[mesh_node].contains("children"));
  const auto scene_nodes = g.doc["scenes"][g.doc.value("scene", 0)]["nodes"].get<std::vector<int>>();
  EXPECT_EQ(std::set<int>(scene_nodes.begin(), scene_nodes.end()), (std::set<int>{mesh_node, arm}));
}

// Each bone's local +Y axis points at its child (Blender draws bones along it; Unity and VRM
// retarget along it): the one child, spine1 for the pelvis, neck for spine3, the pelvis for the
// root bone; a leaf continues its parent's axis.
TEST(Glb, EachBonePointsAtItsChild) {
  const Vertices rest = tube().rest_vertices(Eigen::Vector2d(0.3, 1.0));
  const Glb g = parse_glb(caliper::write_glb(tube(), rest));
  const json& nodes = g.doc["nodes"];
  const std::vector<int> parent_of = node_parents(nodes);
  const json& skin = g.doc["skins"][0];
  std::map<std::string, int> node_of;
  for (const auto& n : skin["joints"]) node_of[nodes[n.get<int>()]["name"]] = n.get<int>();
  auto axis = [&](const std::string& name) { return Eigen::Vector3d(node_world(nodes, parent_of, node_of.at(name)).linear().col(1)); };
  auto at = [&](const std::string& name) { return Eigen::Vector3d(node_world(nodes, parent_of, node_of.at(name)).translation()); };
  const std::pair<const char*, const char*> bones[] = {
      {"root", "pelvis"},          {"pelvis", "spine1"},         {"spine1", "spine2"},     {"spine3", "neck"},
      {"neck", "head"},            {"left_hip", "left_knee"},    {"left_knee", "left_ankle"}, {"left_ankle", "left_foot"},
      {"left_collar", "left_shoulder"}, {"left_shoulder", "left_elbow"}, {"left_elbow", "left_wrist"},
      {"right_wrist", "right_hand"}};
  for (const auto& [bone, child] : bones) {
    const Eigen::Vector3d to_child = (at(child) - at(bone)).normalized();
    EXPECT_GT(axis(bone).dot(to_child), 1 - 1e-9) << bone << " → " << child;
  }
  for (const char* leaf : {"head", "left_foot", "left_hand"}) {
    const std::string parent = nodes[parent_of[static_cast<size_t>(node_of.at(leaf))]]["name"];
    EXPECT_GT(axis(leaf).dot(axis(parent)), 1 - 1e-9) << leaf;
  }
}

TEST(Glb, FourLargestWeightsSumToOneInFloat) {
  const Glb g = parse_glb(caliper::write_glb(tube(), tube().rest_vertices(Eigen::VectorXd())));
  const json& joints_acc = g.doc["accessors"][g.attribute("JOINTS_0")];
  EXPECT_EQ(joints_acc["componentType"], 5121);  // UNSIGNED_BYTE for 24 joints
  EXPECT_EQ(joints_acc["type"], "VEC4");
  const std::vector<double> j = g.read(g.attribute("JOINTS_0"));
  const std::vector<float> w = g.read_floats(g.attribute("WEIGHTS_0"));
  ASSERT_EQ(j.size(), 4u * kVertices);
  ASSERT_EQ(w.size(), 4u * kVertices);
  int nonzero = 0;
  for (int v = 0; v < kVertices; ++v) {
    const float* wv = &w[4 * static_cast<size_t>(v)];
    EXPECT_EQ(((wv[0] + wv[1]) + wv[2]) + wv[3], 1.0f) << "vertex " << v;
    for (int k = 0; k < 4; ++k) {
      EXPECT_GE(wv[k], 0.0f);
      if (wv[k] > 0) ++nonzero;
      else EXPECT_EQ(j[4 * static_cast<size_t>(v) + k], 0) << "unused slot must point at joint 0";
    }
  }
  EXPECT_EQ(nonzero, kInfluencesWritten);
  // Vertex 1: the 4 largest of six, ties to the lower joint, renormalised over .85.
  EXPECT_EQ(std::vector<double>(j.begin() + 4, j.begin() + 8), (std::vector<double>{2, 4, 5, 3}));
  EXPECT_NEAR(w[4], 0.30 / 0.85, 1e-6);
  EXPECT_NEAR(w[5], 0.25 / 0.85, 1e-6);
  EXPECT_NEAR(w[6], 0.20 / 0.85, 1e-6);
  EXPECT_NEAR(w[7], 0.10 / 0.85, 1e-6);
  // Vertex 2: a tie between 23 and 22 goes to 22 first.
  EXPECT_EQ(j[8], 22);
  EXPECT_EQ(j[9], 23);
  // Vertex 0: a single influence is exactly 1.
  EXPECT_EQ(w[0], 1.0f);
  EXPECT_EQ(j[0], 0);
}

TEST(Glb, SameInputSameBytes) {
  const Vertices rest = tube().rest_vertices(Eigen::Vector2d(0.3, 0.1));
  const std::string a = caliper::write_glb(tube(), rest);
  const BodyModel again(tube_data());
  EXPECT_EQ(a, caliper::write_glb(again, Vertices(rest)));
  EXPECT_NE(a, caliper::write_glb(tube(), tube().rest_vertices(Eigen::Vector2d(0.3, 0.2))));
}

TEST(Glb, WithoutSkinIsAPlainMesh) {
  caliper::GlbOptions options;
  options.include_skin = false;
  options.mesh_name = "plain";
  const Glb g = parse_glb(caliper::write_glb(tube(), tube().data().template_vertices, options));
  EXPECT_FALSE(g.doc.contains("skins"));
  EXPECT_EQ(g.attribute("JOINTS_0"), -1);
  EXPECT_EQ(g.attribute("WEIGHTS_0"), -1);
  ASSERT_EQ(g.doc["nodes"].size(), 1u);
  EXPECT_EQ(g.doc["nodes"][0]["name"], "plain");
}

// --morphs: one POSITION target per shape direction, weight 0, named; the tube's directions are
// "taller by 1 % of the height" (β0) and "vertex 5 moves 2 cm along x" (β1).
TEST(Glb, MorphTargetsAreTheShapeDirections) {
  caliper::GlbOptions options;
  options.morphs = true;
  const Vertices rest = tube().rest_vertices(Eigen::Vector2d(0.5, 0.0));
  const Glb g = parse_glb(caliper::write_glb(tube(), rest, options));
  const json& mesh = g.doc["meshes"][0];
  ASSERT_EQ(mesh["primitives"][0]["targets"].size(), 2u);
  EXPECT_EQ(mesh["weights"], json::array({0.0, 0.0}));
  EXPECT_EQ(mesh["extras"]["targetNames"], json::array({"shape_0", "shape_1"}));
  const std::vector<double> taller = g.read(mesh["primitives"][0]["targets"][0]["POSITION"].get<int>());
  const std::vector<double> moved = g.read(mesh["primitives"][0]["targets"][1]["POSITION"].get<int>());
  const Vertices& t = tube().data().template_vertices;
  for (int v = 0; v < kVertices; ++v) {
    EXPECT_NEAR(taller[3 * v + 1], 0.01 * t(v, 1), 1e-7) << v;
    EXPECT_EQ(taller[3 * v], 0.0);
    EXPECT_EQ(moved[3 * v], v == 5 ? 0.02f : 0.0f) << v;
  }
  // Off by default.
  EXPECT_FALSE(parse_glb(caliper::write_glb(tube(), rest)).doc["meshes"][0]["primitives"][0].contains("targets"));
}

TEST(Glb, UncertaintyBecomesACustomAttribute) {
  caliper::GlbOptions options;
  for (int v = 0; v < kVertices; ++v) options.extra_vertex_scalar.push_back(0.001f * static_cast<float>(v));
  const Glb g = parse_glb(caliper::write_glb(tube(), tube().data().template_vertices, options));
  const int acc = g.attribute("_UNCERTAINTY");
  ASSERT_GE(acc, 0);
  EXPECT_EQ(g.doc["accessors"][acc]["type"], "SCALAR");
  EXPECT_EQ(g.doc["accessors"][acc]["componentType"], 5126);
  EXPECT_EQ(g.read_floats(acc), options.extra_vertex_scalar);
}

TEST(Glb, BadInputThrows) {
  const Vertices rest = tube().data().template_vertices;
  Error e = catch_error([&] { caliper::write_glb(tube(), Vertices(rest.topRows(kVertices - 1))); });
  EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
  EXPECT_EQ(e.field(), "vertices");
  Vertices nan = rest;
  nan(7, 1) = std::nan("");
  e = catch_error([&] { caliper::write_glb(tube(), nan); });
  EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
  EXPECT_EQ(e.field(), "vertices");
  Vertices inf = rest;
  inf(3, 0) = INFINITY;
  EXPECT_THROW(caliper::write_glb(tube(), inf), Error);
  caliper::GlbOptions short_extra;
  short_extra.extra_vertex_scalar.assign(3, 0.0f);
  e = catch_error([&] { caliper::write_glb(tube(), rest, short_extra); });
  EXPECT_EQ(e.field(), "extra_vertex_scalar");
  caliper::GlbOptions nan_extra;
  nan_extra.extra_vertex_scalar.assign(kVertices, 0.0f);
  nan_extra.extra_vertex_scalar[4] = NAN;
  e = catch_error([&] { caliper::write_glb(tube(), rest, nan_extra); });
  EXPECT_EQ(e.field(), "extra_vertex_scalar");
  e = catch_error([&] { caliper::save_glb("/nonexistent-dir/x.glb", tube(), rest); });
  EXPECT_EQ(e.kind(), ErrorKind::Io);
}

// A model too big for 16-bit indices and 8-bit joints: 70 000 vertices, a 300-joint chain.
TEST(Glb, LargeModelsUseWideIndicesAndJoints) {
  constexpr int n = 70000, joints = 300;
  BodyModelData d;
  d.name = "wide";
  d.template_vertices.resize(n, 3);
  for (int v = 0; v < n; ++v) d.template_vertices.row(v) << (v % 100) * 0.01, (v / 100) * 0.01, (v % 7) * 0.001;
  // A strip of triangles over the last vertices so indices ≥ 65535 occur.
  d.faces.resize(6, 3);
  for (int t = 0; t < 6; ++t) d.faces.row(t) << n - 100 - t - 2, n - 100 - t - 1, n - t - 1;
  d.shape_directions = Eigen::MatrixXd::Zero(3 * n, 1);
  std::vector<Eigen::Triplet<double>> reg, w;
  for (int j = 0; j < joints; ++j) {
    d.joint_names.push_back(std::string("j").append(std::to_string(j)));
    d.parents.push_back(j - 1);
    reg.emplace_back(j, j * 200, 1.0);
  }
  for (int v = 0; v < n; ++v) w.emplace_back(v, v % joints, 1.0);
  d.joint_regressor.resize(joints, n);
  d.joint_regressor.setFromTriplets(reg.begin(), reg.end());
  d.skin_weights.resize(n, joints);
  d.skin_weights.setFromTriplets(w.begin(), w.end());
  const BodyModel model(std::move(d));
  const Glb g = parse_glb(caliper::write_glb(model, model.data().template_vertices));
  const int indices = g.doc["meshes"][0]["primitives"][0]["indices"];
  EXPECT_EQ(g.doc["accessors"][indices]["componentType"], 5125);
  EXPECT_EQ(g.read(indices)[2], n - 1);
  EXPECT_EQ(g.doc["accessors"][g.attribute("JOINTS_0")]["componentType"], 5123);
  const std::vector<double> j = g.read(g.attribute("JOINTS_0"));
  EXPECT_EQ(j[4 * 299], 299);
  EXPECT_EQ(j[4 * 69999], 69999 % joints);
  EXPECT_EQ(g.doc["skins"][0]["joints"].size(), static_cast<size_t>(joints) + 1);  // and the root bone
}

// ---- independent readers ----------------------------------------------------------------------

#ifdef CALIPER_HAVE_ASSIMP
TEST(GlbAssimp, ReadsBackSkinnedMesh) {
  const Vertices rest = tube().rest_vertices(Eigen::Vector2d(1.0, 1.0));
  const std::string bytes = caliper::write_glb(tube(), rest);
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), aiProcess_ValidateDataStructure, "glb");
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  ASSERT_EQ(scene->mNumMeshes, 1u);
  const aiMesh* mesh = scene->mMeshes[0];
  EXPECT_EQ(mesh->mNumVertices, static_cast<unsigned>(kVertices));
  EXPECT_EQ(mesh->mNumFaces, static_cast<unsigned>(tube().face_count()));
  for (int v = 0; v < kVertices; ++v)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(mesh->mVertices[v][c], rest(v, c), 1e-6);
  ASSERT_TRUE(mesh->HasBones());
  EXPECT_GE(mesh->mNumBones, 24u);  // the root bone moves no vertex: Assimp may leave it out
  std::vector<double> sum(kVertices, 0.0);
  unsigned total = 0;
  std::set<std::string> bone_names;
  for (unsigned b = 0; b < mesh->mNumBones; ++b) {
    const aiBone* bone = mesh->mBones[b];
    bone_names.insert(bone->mName.C_Str());
    for (unsigned k = 0; k < bone->mNumWeights; ++k) {
      if (bone->mWeights[k].mWeight <= 0) continue;  // placeholders for joints without influence
      ASSERT_LT(bone->mWeights[k].mVertexId, static_cast<unsigned>(kVertices));
      sum[bone->mWeights[k].mVertexId] += bone->mWeights[k].mWeight;
      ++total;
    }
  }
  for (int v = 0; v < kVertices; ++v) EXPECT_NEAR(sum[v], 1.0, 1e-6) << "vertex " << v;
  EXPECT_EQ(total, static_cast<unsigned>(kInfluencesWritten));
  auto names = caliper::smpl_joint_names();
  bone_names.erase("root");
  EXPECT_EQ(bone_names, std::set<std::string>(names.begin(), names.end()));
  // The pelvis bone's offset matrix is our inverse bind matrix: it takes the pelvis (vertex 1)
  // to the origin.
  for (unsigned b = 0; b < mesh->mNumBones; ++b)
    if (std::string(mesh->mBones[b]->mName.C_Str()) == "pelvis") {
      const aiVector3D p = mesh->mBones[b]->mOffsetMatrix * aiVector3D(rest(1, 0), rest(1, 1), rest(1, 2));
      EXPECT_NEAR(p.Length(), 0.0, 1e-6);
    }
}

// FBX read back by Assimp, an independent reader (which keeps the file's numbers): the mesh at
// its size in centimetres, declared by UnitScaleFactor 1, the node tree root → pelvis → …, every vertex's weights summing to 1,
// and each bone's offset (inverse bind) matrix taking its joint to the origin.
TEST(FbxAssimp, ReadsBackMeshSkeletonWeightsAndBindPose) {
  const Vertices rest = tube().rest_vertices(Eigen::Vector2d(1.0, 1.0));
  const std::string bytes = caliper::write_fbx(tube(), rest);
  ASSERT_GT(bytes.size(), 27u);
  EXPECT_EQ(bytes.substr(0, 21), std::string("Kaydara FBX Binary  \0", 21));
  std::uint32_t version = 0;
  std::memcpy(&version, bytes.data() + 23, 4);
  EXPECT_EQ(version, 7400u);
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFileFromMemory(
      bytes.data(), bytes.size(), aiProcess_ValidateDataStructure | aiProcess_JoinIdenticalVertices, "fbx");
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  ASSERT_EQ(scene->mNumMeshes, 1u);
  const aiMesh* mesh = scene->mMeshes[0];
  EXPECT_EQ(mesh->mNumVertices, static_cast<unsigned>(kVertices));
  EXPECT_EQ(mesh->mNumFaces, static_cast<unsigned>(tube().face_count()));
  // Every written vertex is one of the model's, at the model's position in centimetres.
  for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
    double best = 1e9;
    for (int k = 0; k < kVertices; ++k)
      best = std::min(best, (Eigen::Vector3d(mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z) - 100.0 * rest.row(k).transpose()).norm());
    EXPECT_LT(best, 1e-4) << "vertex " << v;
  }
  ASSERT_NE(scene->mMetaData, nullptr);
  double scale = 0;
  float scale_f = 0;  // Assimp keeps FBX doubles as float or double depending on the version
  if (!scene->mMetaData->Get("UnitScaleFactor", scale) && scene->mMetaData->Get("UnitScaleFactor", scale_f)) scale = scale_f;
  EXPECT_EQ(scale, 1.0);  // centimetres per file unit
  int up = -1;
  ASSERT_TRUE(scene->mMetaData->Get("UpAxis", up));
  EXPECT_EQ(up, 1);
  // Weights: per vertex (by position) they sum to 1.
  std::vector<double> sum(mesh->mNumVertices, 0.0);
  std::map<std::string, const aiBone*> bones;
  for (unsigned b = 0; b < mesh->mNumBones; ++b) {
    const aiBone* bone = mesh->mBones[b];
    bones[bone->mName.C_Str()] = bone;
    for (unsigned k = 0; k < bone->mNumWeights; ++k) sum[bone->mWeights[k].mVertexId] += bone->mWeights[k].mWeight;
  }
  for (unsigned v = 0; v < mesh->mNumVertices; ++v) EXPECT_NEAR(sum[v], 1.0, 1e-6) << "vertex " << v;
  EXPECT_GE(bones.size(), 24u);
  // Bind pose: each joint's offset matrix maps the joint's rest position to the origin.
  auto joint = [&](int j) -> Eigen::Vector3d {  // centimetres, as in the file
    return 100.0 * (j < 22 ? Eigen::Vector3d(rest.row(1 + j).transpose()) : Eigen::Vector3d(0.5 * (rest.row(23) + rest.row(24)).transpose()));
  };
  const auto& names = caliper::smpl_joint_names();
  for (int j = 0; j < 24; ++j) {
    const auto it = bones.find(names[j]);
    if (it == bones.end()) continue;  // a joint that moves no vertex has no bone in Assimp
    const aiVector3D p = it->second->mOffsetMatrix * aiVector3D(joint(j).x(), joint(j).y(), joint(j).z());
    EXPECT_LT(p.Length(), 1e-4) << names[j];
  }
  // The node tree: root (on the floor) → pelvis → left_hip → left_knee, at the joints' places.
  const aiNode* root = scene->mRootNode->FindNode("root");
  ASSERT_NE(root, nullptr);
  const aiNode* pelvis = root->FindNode("pelvis");
  ASSERT_NE(pelvis, nullptr);
  EXPECT_EQ(pelvis->mParent, root);
  const aiNode* knee = scene->mRootNode->FindNode("left_knee");
  ASSERT_NE(knee, nullptr);
  EXPECT_EQ(std::string(knee->mParent->mName.C_Str()), "left_hip");
  aiMatrix4x4 world;
  for (const aiNode* n = knee; n; n = n->mParent) world = n->mTransformation * world;
  const aiVector3D at = world * aiVector3D(0, 0, 0);
  EXPECT_NEAR(at.x, joint(4).x(), 1e-4);
  EXPECT_NEAR(at.y, joint(4).y(), 1e-4);
  EXPECT_NEAR(at.z, joint(4).z(), 1e-4);
}

TEST(FbxAssimp, HumanoidNamesAndProvenanceProperties) {
  caliper::ExportOptions options;
  options.skeleton = caliper::SkeletonNaming::Humanoid;
  const std::string bytes = caliper::write_fbx(tube(), tube().data().template_vertices, options);
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), aiProcess_ValidateDataStructure, "fbx");
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  for (const char* name : {"Root", "Hips", "LeftUpperLeg", "LeftFoot", "LeftToes", "LeftShoulder", "LeftUpperArm", "Head"})
    EXPECT_NE(scene->mRootNode->FindNode(name), nullptr) << name;
  EXPECT_EQ(scene->mRootNode->FindNode("pelvis"), nullptr);
  // The tube has no licence: the file says so and refuses commercial use.
  EXPECT_NE(bytes.find("non-commercial use only"), std::string::npos);
  EXPECT_NE(bytes.find("caliper_licence"), std::string::npos);
}

// --morphs in FBX: Assimp turns the blend shapes into one anim mesh per shape direction, each the
// mesh with that direction applied at full weight (the tube's β0 makes every point 1 % of its
// template height taller, β1 moves vertex 5 by 2 cm along x and nothing else).
TEST(FbxAssimp, BlendShapesAreTheShapeDirections) {
  caliper::ExportOptions options;
  options.morphs = true;
  const Vertices rest = tube().rest_vertices(Eigen::Vector2d(0.5, 0.0));
  const std::string bytes = caliper::write_fbx(tube(), rest, options);
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), aiProcess_ValidateDataStructure, "fbx");
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  ASSERT_EQ(scene->mNumMeshes, 1u);
  const aiMesh* mesh = scene->mMeshes[0];
  ASSERT_EQ(mesh->mNumAnimMeshes, 2u);
  const Vertices& t = tube().data().template_vertices;
  std::set<std::string> names;
  for (unsigned a = 0; a < 2; ++a) {
    const aiAnimMesh* target = mesh->mAnimMeshes[a];
    names.insert(target->mName.C_Str());
    const bool taller = std::string(target->mName.C_Str()) == "shape_0";
    ASSERT_EQ(target->mNumVertices, mesh->mNumVertices);
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      // Assimp writes a vertex per triangle corner: find the model's vertex by its position
      // (the file's centimetres, back in metres).
      const Eigen::Vector3d at = 0.01 * Eigen::Vector3d(mesh->mVertices[v].x, mesh->mVertices[v].y, mesh->mVertices[v].z);
      int k = 0;
      for (int i = 1; i < kVertices; ++i)
        if ((rest.row(i).transpose() - at).norm() < (rest.row(k).transpose() - at).norm()) k = i;
      ASSERT_LT((rest.row(k).transpose() - at).norm(), 1e-6);
      const Eigen::Vector3d expected = taller ? Eigen::Vector3d(0, 0.01 * t(k, 1), 0)
                                              : Eigen::Vector3d(k == 5 ? 0.02 : 0.0, 0, 0);
      const Eigen::Vector3d moved = 0.01 * Eigen::Vector3d(target->mVertices[v].x, target->mVertices[v].y,
                                                           target->mVertices[v].z) - at;
      EXPECT_LT((moved - expected).norm(), 1e-6) << target->mName.C_Str() << " at vertex " << k;
    }
  }
  EXPECT_EQ(names, (std::set<std::string>{"shape_0", "shape_1"}));
  // Off by default.
  const std::string plain = caliper::write_fbx(tube(), rest);
  const aiScene* without = importer.ReadFileFromMemory(plain.data(), plain.size(), aiProcess_ValidateDataStructure, "fbx");
  ASSERT_NE(without, nullptr) << importer.GetErrorString();
  EXPECT_EQ(without->mMeshes[0]->mNumAnimMeshes, 0u);
  EXPECT_EQ(plain.find("BlendShape"), std::string::npos);
}

TEST(Fbx, BadInputThrows) {
  Vertices rest = tube().data().template_vertices;
  EXPECT_EQ(catch_error([&] { caliper::write_fbx(tube(), rest.topRows(3)); }).field(), "vertices");
  rest(2, 1) = std::nan("");
  EXPECT_EQ(catch_error([&] { caliper::write_fbx(tube(), rest); }).field(), "vertices");
}
#else
TEST(GlbAssimp, ReadsBackSkinnedMesh) { FAIL() << "built without Assimp: install libassimp-dev (scripts/install-deps.sh)"; }
TEST(FbxAssimp, ReadsBackMeshSkeletonWeightsAndBindPose) { FAIL() << "built without Assimp: install libassimp-dev"; }
#endif

namespace {

// Why the Khronos validator (node + tools/node_modules/gltf-validator) cannot run here, or "".
std::string khronos_validator_missing() {
  const fs::path tools = fs::path(CALIPER_SOURCE_DIR) / "tools";
  if (std::system("node --version > /dev/null 2>&1") != 0)
    return "node is not installed: run scripts/install-deps.sh";
  if (!fs::exists(tools / "node_modules" / "gltf-validator"))
    return "the Khronos validator is missing: run scripts/install-deps.sh (or `cd tools && npm ci`)";
  return "";
}

// CALIPER_REQUIRE_TOOLS=1 (set by scripts/test.sh, so in CI, after install-deps.sh) turns a
// missing external checker into a failure; elsewhere the test is reported as skipped.
bool tools_required() {
  const char* v = std::getenv("CALIPER_REQUIRE_TOOLS");
  return v != nullptr && std::string(v) == "1";
}

// Runs tools/validate-gltf.mjs on one file; returns its JSON summary (an object), or null after
// recording a failure when the validator ran but gave no report.
json khronos_validate(const fs::path& file) {
  const fs::path tools = fs::path(CALIPER_SOURCE_DIR) / "tools";
  const std::string cmd = "node '" + (tools / "validate-gltf.mjs").string() + "' '" + file.string() + "' 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) { ADD_FAILURE() << "cannot run " << cmd; return {}; }
  std::string out;
  char buf[4096];
  for (size_t got; (got = fread(buf, 1, sizeof buf, pipe)) > 0;) out.append(buf, got);
  const int status = pclose(pipe);
  json summary = json::parse(out, nullptr, false);
  if (summary.is_discarded() || !summary.is_object()) {
    ADD_FAILURE() << "validator output is not a JSON report: " << out;
    return {};
  }
  EXPECT_EQ(status == 0, summary.value("numErrors", 1) == 0) << out;
  return summary;
}

}  // namespace

// Skips the test with the reason when the validator cannot run (fails instead when
// CALIPER_REQUIRE_TOOLS=1); both return from the test body, so nothing reads a missing report.
#define REQUIRE_KHRONOS_VALIDATOR()                                              \
  do {                                                                           \
    if (const std::string why = khronos_validator_missing(); !why.empty()) {     \
      if (tools_required()) FAIL() << why << " (CALIPER_REQUIRE_TOOLS=1)";       \
      GTEST_SKIP() << why;                                                       \
    }                                                                            \
  } while (0)

TEST(GlbKhronosValidator, SkinnedAvatarHasNoErrorsOrWarnings) {
  REQUIRE_KHRONOS_VALIDATOR();
  const fs::path dir = temp_dir();
  caliper::GlbOptions options;
  for (int v = 0; v < kVertices; ++v) options.extra_vertex_scalar.push_back(0.01f);
  caliper::save_glb((dir / "tube.glb").string(), tube(), tube().rest_vertices(Eigen::Vector2d(1.0, -1.0)), options);
  const json s = khronos_validate(dir / "tube.glb");
  ASSERT_TRUE(s.is_object());
  EXPECT_EQ(s.value("numErrors", -1), 0) << s.dump(1);
  EXPECT_EQ(s.value("numWarnings", -1), 0) << s.dump(1);
  EXPECT_TRUE(s["info"].value("hasSkins", false)) << s.dump(1);
  EXPECT_EQ(s["info"].value("totalVertexCount", 0), kVertices);
  fs::remove_all(dir);
}

TEST(GlbKhronosValidator, VrmHasNoErrorsOrWarnings) {
  REQUIRE_KHRONOS_VALIDATOR();
  const fs::path dir = temp_dir();
  caliper::save_vrm((dir / "tube.vrm").string(), tube(), tube().rest_vertices(Eigen::Vector2d(1.0, -1.0)));
  const json s = khronos_validate(dir / "tube.vrm");
  ASSERT_TRUE(s.is_object());
  EXPECT_EQ(s.value("numErrors", -1), 0) << s.dump(1);
  EXPECT_EQ(s.value("numWarnings", -1), 0) << s.dump(1);
  EXPECT_TRUE(s["info"].value("hasSkins", false)) << s.dump(1);
  fs::remove_all(dir);
}

TEST(GlbKhronosValidator, MorphTargetsHaveNoErrorsOrWarnings) {
  REQUIRE_KHRONOS_VALIDATOR();
  const fs::path dir = temp_dir();
  caliper::GlbOptions options;
  options.morphs = true;
  caliper::save_glb((dir / "morphs.glb").string(), tube(), tube().rest_vertices(Eigen::Vector2d(1.0, -1.0)), options);
  const json s = khronos_validate(dir / "morphs.glb");
  ASSERT_TRUE(s.is_object());
  EXPECT_EQ(s.value("numErrors", -1), 0) << s.dump(1);
  EXPECT_EQ(s.value("numWarnings", -1), 0) << s.dump(1);
  fs::remove_all(dir);
}

TEST(GlbKhronosValidator, PlainMeshHasNoErrors) {
  REQUIRE_KHRONOS_VALIDATOR();
  const fs::path dir = temp_dir();
  caliper::GlbOptions options;
  options.include_skin = false;
  caliper::save_glb((dir / "plain.glb").string(), tube(), tube().data().template_vertices, options);
  const json s = khronos_validate(dir / "plain.glb");
  ASSERT_TRUE(s.is_object());
  EXPECT_EQ(s.value("numErrors", -1), 0) << s.dump(1);
  EXPECT_EQ(s.value("numWarnings", -1), 0) << s.dump(1);
  fs::remove_all(dir);
}

TEST(GlbKhronosValidator, CatchesABrokenFile) {
  REQUIRE_KHRONOS_VALIDATOR();
  // The check must be able to fail: a GLB whose declared length lies is an error.
  const fs::path dir = temp_dir();
  std::string bytes = caliper::write_glb(tube(), tube().data().template_vertices);
  bytes.resize(bytes.size() - 8);
  write_text(dir / "broken.glb", bytes);
  const json s = khronos_validate(dir / "broken.glb");
  ASSERT_TRUE(s.is_object());
  EXPECT_GT(s.value("numErrors", 0), 0) << s.dump(1);
  fs::remove_all(dir);
}

// ---- OBJ --------------------------------------------------------------------------------------

TEST(Obj, WriteLayout) {
  Vertices v(4, 3);
  v << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  Faces f(4, 3);
  f << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  const std::string text = caliper::write_obj(v, f, "a tetrahedron\nsecond line");
  EXPECT_EQ(text.rfind("# a tetrahedron\n# second line\n#", 0), 0u) << text;
  EXPECT_NE(text.find("\nv 1 0 0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nf 1//1 3//3 2//2\n"), std::string::npos) << text;
  EXPECT_NE(text.find("\nf 2//2 3//3 4//4\n"), std::string::npos) << text;
  int vn = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) vn += line.rfind("vn ", 0) == 0;
  EXPECT_EQ(vn, 4);
  EXPECT_THROW(caliper::write_obj(v, Faces(Faces::Constant(1, 3, 4))), Error);
}

TEST(Obj, RoundTripIsExact) {
  const fs::path dir = temp_dir();
  const Vertices rest = tube().rest_vertices(Eigen::Vector2d(0.123456789, -1.5));
  write_text(dir / "tube.obj", caliper::write_obj(rest, tube().faces(), "tube"));
  const caliper::Mesh mesh = caliper::read_obj((dir / "tube.obj").string());
  EXPECT_EQ(mesh.vertices, rest);  // shortest round-trip decimals: bit-exact
  EXPECT_EQ(mesh.faces, tube().faces());
  fs::remove_all(dir);
}

TEST(Obj, ReadsPolygonsNegativeIndicesCommentsAndCrlf) {
  const fs::path dir = temp_dir();
  write_text(dir / "mixed.obj",
             "# comment line\r\n"
             "mtllib x.mtl\r\n"
             "o thing\r\n"
             "v 0 0 0\r\n"
             "v 1 0 0   # trailing comment\r\n"
             "v 1 1 0 1.0\r\n"
             "v 0 1 0 0.5 0.5 0.5\r\n"
             "v +2.5e0 -1E-1 .5\r\n"
             "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
             "vn 0 0 1\n"
             "\n"
             "g quad\ns off\nusemtl skin\n"
             "f 1/1/1 2/2/1 3/3/1 4/4/1\n"      // quad → (0,1,2), (0,2,3)
             "f -4/1 -3/2 \\\n -1/3\n"          // relative, continued: (1,2,4)
             "f 5//1 1//1 2//1 4//1 3//1\n");   // pentagon → 3 triangles
  const caliper::Mesh mesh = caliper::read_obj((dir / "mixed.obj").string());
  ASSERT_EQ(mesh.vertices.rows(), 5);
  EXPECT_EQ(mesh.vertices.row(4), Eigen::RowVector3d(2.5, -0.1, 0.5));
  EXPECT_EQ(mesh.vertices.row(2), Eigen::RowVector3d(1, 1, 0));
  Faces expected(6, 3);
  expected << 0, 1, 2, 0, 2, 3, 1, 2, 4, 4, 0, 1, 4, 1, 3, 4, 3, 2;
  EXPECT_EQ(mesh.faces, expected);
  fs::remove_all(dir);
}

TEST(Obj, ErrorsNameTheLine) {
  const fs::path dir = temp_dir();
  struct Case {
    const char* text;
    const char* needle;  // expected in the message
  };
  const Case cases[] = {
      {"v 0 0 0\nv 1 0 0\nv 0 1 x\nf 1 2 3\n", ":3:"},                  // malformed number
      {"v 0 0 0\nv 1 0 0\nv 0 1 1e999\nf 1 2 3\n", ":3:"},              // overflow
      {"v 0 0 0\nv 1 0 0\nv 0 1 nan\nf 1 2 3\n", ":3:"},                // NaN
      {"v 0 0\nf 1 1 1\n", ":1:"},                                      // too few coordinates
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n", ":5:"},                // index past the end
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", ":4:"},                  // index 0
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n", ":4:"},               // relative before start
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", ":4:"},                    // too few corners
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3.5\n", ":4:"},                // non-integer index
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//2 3//1\n", ":5:"},  // normal out of range
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces"},
      {"", "no faces"},
  };
  for (const Case& c : cases) {
    write_text(dir / "bad.obj", c.text);
    const Error e = catch_error([&] { caliper::read_obj((dir / "bad.obj").string()); });
    EXPECT_EQ(e.kind(), ErrorKind::Format) << c.text;
    EXPECT_NE(std::string(e.what()).find(c.needle), std::string::npos) << e.what() << "\nfor:\n" << c.text;
  }
  EXPECT_EQ(catch_error([&] { caliper::read_obj((dir / "missing.obj").string()); }).kind(), ErrorKind::Io);
  EXPECT_EQ(catch_error([&] { caliper::read_obj(dir.string()); }).kind(), ErrorKind::Io);
  fs::remove_all(dir);
}

// ---- texture coordinates -----------------------------------------------------------------------

namespace {

// The tube with a UV layout: its side cut open along column 0 (ring r, column k at
// u = 0.1·(4 − k), v = 0.1 + 0.15·r; column 4 is column 0 again) and each cap its own island,
// the ring's corners around the centre. Side: 6 rings × 5 UVs; caps: 5 UVs each.
// Vertices with more than one UV: column 0 of every ring (2 side UVs: 6 copies) and the corners
// of rings 0 and 5 (a side UV and a cap UV: 8 copies), so the glb has 26 + 6 + 8 = 40 vertices.
constexpr int kSplitVertices = kVertices + kRings + 8;

BodyModelData tube_with_uvs() {
  BodyModelData d = tube_data();
  const Faces& f = d.faces;
  std::vector<std::array<double, 2>> uv;
  for (int r = 0; r < kRings; ++r)
    for (int k = 0; k <= 4; ++k) uv.push_back({0.1 * (4 - k), 0.1 + 0.15 * r});
  const double corner[4][2] = {{0.1, 0.05}, {-0.1, 0.05}, {-0.1, -0.05}, {0.1, -0.05}};  // the ring's x, z halved
  const int bottom = static_cast<int>(uv.size());
  uv.push_back({0.75, 0.2});
  for (auto& c : corner) uv.push_back({0.75 + c[0], 0.2 + c[1]});
  const int top = static_cast<int>(uv.size());
  uv.push_back({0.75, 0.6});
  for (auto& c : corner) uv.push_back({0.75 + c[0], 0.6 - c[1]});  // seen from above: z points down
  d.uv_coordinates.resize(static_cast<Eigen::Index>(uv.size()), 2);
  for (size_t i = 0; i < uv.size(); ++i) d.uv_coordinates.row(static_cast<Eigen::Index>(i)) << uv[i][0], uv[i][1];
  d.uv_faces.resize(f.rows(), 3);
  for (Eigen::Index i = 0; i < f.rows(); ++i) {
    const bool bottom_cap = f(i, 0) == 0, top_cap = f(i, 0) == kVertices - 1;
    int column[3];
    for (int c = 0; c < 3; ++c) column[c] = (f(i, c) - 1) % 4;
    const bool wraps = std::max({column[0], column[1], column[2]}) == 3;
    for (int c = 0; c < 3; ++c) {
      const int v = f(i, c);
      if (bottom_cap) d.uv_faces(i, c) = v == 0 ? bottom : bottom + 1 + column[c];
      else if (top_cap) d.uv_faces(i, c) = v == kVertices - 1 ? top : top + 1 + column[c];
      else d.uv_faces(i, c) = (v - 1) / 4 * 5 + (column[c] == 0 && wraps ? 4 : column[c]);
    }
  }
  return d;
}

const BodyModel& textured_tube() {
  static const BodyModel model(tube_with_uvs());
  return model;
}

}  // namespace

TEST(ExportFixture, TexturedTubeLayoutIsValid) {
  const auto& d = textured_tube().data();
  EXPECT_GT(caliper::uv_signed_areas(d.uv_coordinates, d.uv_faces).minCoeff(), 0.0);  // counter-clockwise
  EXPECT_TRUE(caliper::uv_overlaps(d.uv_coordinates, d.uv_faces).empty());
}

TEST(GlbTexcoords, SplitOnlyAtSeamsWithTheUnsplitPositionsNormalsAndSkin) {
  const Vertices rest = textured_tube().rest_vertices(Eigen::Vector2d(0.5, 1.0));
  caliper::GlbOptions options;
  for (int v = 0; v < kVertices; ++v) options.extra_vertex_scalar.push_back(0.001f * v);
  const Glb g = parse_glb(caliper::write_glb(textured_tube(), rest, options));
  const Glb plain = parse_glb(caliper::write_glb(tube(), rest, options));
  ASSERT_GE(g.attribute("TEXCOORD_0"), 0);
  EXPECT_EQ(plain.attribute("TEXCOORD_0"), -1);  // no layout, no texture coordinates
  const std::vector<float> pos = g.read_floats(g.attribute("POSITION"));
  const std::vector<float> nor = g.read_floats(g.attribute("NORMAL"));
  const std::vector<float> tex = g.read_floats(g.attribute("TEXCOORD_0"));
  const std::vector<double> joints = g.read(g.attribute("JOINTS_0")), weights = g.read(g.attribute("WEIGHTS_0"));
  const std::vector<float> extra = g.read_floats(g.attribute("_UNCERTAINTY"));
  const std::vector<float> plain_nor = plain.read_floats(plain.attribute("NORMAL"));
  const std::vector<double> plain_joints = plain.read(plain.attribute("JOINTS_0")), plain_weights = plain.read(plain.attribute("WEIGHTS_0"));
  ASSERT_EQ(pos.size(), 3u * kSplitVertices);
  ASSERT_EQ(tex.size(), 2u * kSplitVertices);
  ASSERT_EQ(extra.size(), static_cast<size_t>(kSplitVertices));
  const std::vector<double> idx = g.read(g.doc["meshes"][0]["primitives"][0]["indices"].get<int>());
  const caliper::Faces& faces = textured_tube().faces();
  const auto& uv = textured_tube().data().uv_coordinates;
  const auto& uv_faces = textured_tube().data().uv_faces;
  ASSERT_EQ(idx.size(), static_cast<size_t>(faces.size()));
  std::vector<int> source(kSplitVertices, -1);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      const int out = static_cast<int>(idx[static_cast<size_t>(3 * f + c)]), v = faces(f, c);
      // The first N vertices are the model's own; copies come after.
      if (out < kVertices) {
        EXPECT_EQ(out, v);
      }
      source[static_cast<size_t>(out)] = v;
      // glTF's v runs down from the top-left: (u, 1 − v).
      EXPECT_FLOAT_EQ(tex[2 * out], static_cast<float>(uv(uv_faces(f, c), 0)));
      EXPECT_FLOAT_EQ(tex[2 * out + 1], static_cast<float>(1.0 - uv(uv_faces(f, c), 1)));
    }
  for (int out = 0; out < kSplitVertices; ++out) {
    const int v = source[static_cast<size_t>(out)];
    ASSERT_GE(v, 0) << "vertex " << out << " unused";
    for (int c = 0; c < 3; ++c) {
      EXPECT_EQ(pos[3 * out + c], static_cast<float>(rest(v, c))) << out;  // the unsplit position
      EXPECT_EQ(nor[3 * out + c], plain_nor[3 * v + c]) << out;            // the unsplit mesh's normal
    }
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(joints[4 * out + k], plain_joints[4 * v + k]);
      EXPECT_EQ(weights[4 * out + k], plain_weights[4 * v + k]);
    }
    EXPECT_EQ(extra[static_cast<size_t>(out)], options.extra_vertex_scalar[static_cast<size_t>(v)]);
  }
  // Only seam vertices were copied: column 0 of every ring and the corners of the end rings.
  for (int out = kVertices; out < kSplitVertices; ++out) {
    const int v = source[static_cast<size_t>(out)];
    const int ring = (v - 1) / 4, column = (v - 1) % 4;
    EXPECT_TRUE(column == 0 || ring == 0 || ring == kRings - 1) << "vertex " << v;
  }
  EXPECT_EQ(g.doc["accessors"][g.attribute("TEXCOORD_0")]["type"], "VEC2");
}

TEST(GlbTexcoords, ValidatorAndAssimpAcceptIt) {
  REQUIRE_KHRONOS_VALIDATOR();
  const fs::path dir = temp_dir();
  caliper::GlbOptions options;
  for (int v = 0; v < kVertices; ++v) options.extra_vertex_scalar.push_back(0.01f);
  const Vertices rest = textured_tube().rest_vertices(Eigen::Vector2d(1.0, -1.0));
  caliper::save_glb((dir / "tube-uv.glb").string(), textured_tube(), rest, options);
  const json s = khronos_validate(dir / "tube-uv.glb");
  ASSERT_TRUE(s.is_object());
  EXPECT_EQ(s.value("numErrors", -1), 0) << s.dump(1);
  EXPECT_EQ(s.value("numWarnings", -1), 0) << s.dump(1);
  EXPECT_EQ(s["info"].value("totalVertexCount", 0), kSplitVertices) << s.dump(1);
#ifdef CALIPER_HAVE_ASSIMP
  const std::string bytes = caliper::write_glb(textured_tube(), rest, options);
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), aiProcess_ValidateDataStructure, "glb");
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  const aiMesh* mesh = scene->mMeshes[0];
  EXPECT_EQ(mesh->mNumVertices, static_cast<unsigned>(kSplitVertices));
  ASSERT_TRUE(mesh->HasTextureCoords(0));
  // Assimp flips glTF's v back to OBJ's convention (v up) by default.
  const auto& uv = textured_tube().data().uv_coordinates;
  const auto& uv_faces = textured_tube().data().uv_faces;
  for (unsigned f = 0; f < mesh->mNumFaces; ++f)
    for (unsigned c = 0; c < 3; ++c) {
      const aiVector3D t = mesh->mTextureCoords[0][mesh->mFaces[f].mIndices[c]];
      EXPECT_NEAR(t.x, uv(uv_faces(f, c), 0), 1e-6);
      EXPECT_NEAR(t.y, uv(uv_faces(f, c), 1), 1e-6);
    }
#endif
  fs::remove_all(dir);
}

TEST(ObjTexcoords, WrittenAndReadBack) {
  const fs::path dir = temp_dir();
  const Vertices rest = textured_tube().rest_vertices(Eigen::Vector2d(0.25, 0.5));
  const auto& d = textured_tube().data();
  const std::string text = caliper::write_obj(rest, d.faces, d.uv_coordinates, d.uv_faces, "textured tube");
  EXPECT_NE(text.find("\nvt 0.4 0.1\n"), std::string::npos) << text;  // ring 0, column 0
  // Face 4 is the first side face: vertices 1, 5, 6 with UVs 0, 5, 6 (1-based: +1).
  EXPECT_NE(text.find("\nf 2/1/2 6/6/6 7/7/7\n"), std::string::npos) << text;
  write_text(dir / "tube-uv.obj", text);
  const caliper::TexturedMesh back = caliper::read_obj_textured((dir / "tube-uv.obj").string());
  EXPECT_EQ(back.mesh.vertices, rest);
  EXPECT_EQ(back.mesh.faces, d.faces);
  EXPECT_EQ(back.uv_coordinates, d.uv_coordinates);  // shortest round-trip decimals: exact
  EXPECT_EQ(back.uv_faces, d.uv_faces);
  // Without UVs: no vt lines, `v//vn` corners, and nothing read back.
  write_text(dir / "tube.obj", caliper::write_obj(rest, d.faces, "plain"));
  EXPECT_EQ(caliper::read_obj_textured((dir / "tube.obj").string()).uv_faces.rows(), 0);
  // Mismatched UV faces are refused.
  EXPECT_THROW(caliper::write_obj(rest, d.faces, d.uv_coordinates, caliper::Faces(d.uv_faces.topRows(3))), Error);
  fs::remove_all(dir);
}
