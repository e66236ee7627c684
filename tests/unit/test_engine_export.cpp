// The engine-facing parts of the avatar exports: humanoid bone names, rest orientations of the
// built-in body's 54-joint rig, the root bone, and the provenance written into the files.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <fstream>
#include <algorithm>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "caliper/caliper.h"
#include "fixtures.h"

#ifdef CALIPER_HAVE_ASSIMP
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#endif

using namespace caliper;
using nlohmann::json;

namespace {

json glb_document(const std::string& glb) {
  std::uint32_t length = 0;
  std::memcpy(&length, glb.data() + 12, 4);
  return json::parse(glb.substr(20, length));
}

const BodyModel& mannequin() {
  static const BodyModel m = load_model("mannequin", Sex::Female);
  return m;
}

// Unity's HumanBodyBones that a Humanoid avatar requires (Unity manual, "Humanoid Avatars"),
// each with the bone it must descend from.
const std::map<std::string, std::string> kUnityRequired = {
    {"Hips", ""},
    {"Spine", "Hips"},
    {"Head", "Spine"},
    {"LeftUpperLeg", "Hips"},
    {"LeftLowerLeg", "LeftUpperLeg"},
    {"LeftFoot", "LeftLowerLeg"},
    {"RightUpperLeg", "Hips"},
    {"RightLowerLeg", "RightUpperLeg"},
    {"RightFoot", "RightLowerLeg"},
    {"LeftUpperArm", "Spine"},
    {"LeftLowerArm", "LeftUpperArm"},
    {"LeftHand", "LeftLowerArm"},
    {"RightUpperArm", "Spine"},
    {"RightLowerArm", "RightUpperArm"},
    {"RightHand", "RightLowerArm"},
};

}  // namespace

TEST(HumanoidNames, SmplsOneOffNamesMapToTheBoneTheyStart) {
  // SMPL names a joint, an engine the bone that starts there.
  const std::map<std::string, std::string> expected = {
      {"pelvis", "Hips"},          {"left_hip", "LeftUpperLeg"},    {"left_knee", "LeftLowerLeg"},
      {"left_ankle", "LeftFoot"},  {"left_foot", "LeftToes"},       {"left_collar", "LeftShoulder"},
      {"left_shoulder", "LeftUpperArm"}, {"left_elbow", "LeftLowerArm"}, {"left_wrist", "LeftHand"},
      {"right_shoulder", "RightUpperArm"}, {"spine1", "Spine"},     {"spine2", "Chest"},
      {"spine3", "UpperChest"},    {"left_thumb1", "LeftThumbProximal"}, {"left_pinky3", "LeftLittleDistal"}};
  for (const auto& [smpl, humanoid] : expected) {
    const HumanoidBone* b = find_humanoid_bone(smpl);
    ASSERT_NE(b, nullptr) << smpl;
    EXPECT_EQ(std::string(b->humanoid), humanoid) << smpl;
  }
  EXPECT_EQ(std::string(find_humanoid_bone("left_thumb1")->vrm), "leftThumbMetacarpal");
  EXPECT_EQ(std::string(find_humanoid_bone("left_thumb2")->vrm), "leftThumbProximal");
  EXPECT_EQ(std::string(find_humanoid_bone("left_index2")->vrm), "leftIndexIntermediate");
  EXPECT_EQ(find_humanoid_bone("no_such_joint"), nullptr);
  // Every rig joint has a row, and no two rows share an engine name.
  std::set<std::string> seen;
  for (const auto& name : rig_joint_names()) {
    const HumanoidBone* b = find_humanoid_bone(name);
    ASSERT_NE(b, nullptr) << name;
    EXPECT_TRUE(seen.insert(b->humanoid).second) << b->humanoid;
  }
}

TEST(HumanoidNames, ParseRefusesOtherNamingsNamingTheField) {
  EXPECT_EQ(parse_skeleton_naming("smpl"), SkeletonNaming::Smpl);
  EXPECT_EQ(parse_skeleton_naming("humanoid"), SkeletonNaming::Humanoid);
  const Error e = test::catch_error([] { parse_skeleton_naming("mixamo", "--skeleton"); });
  EXPECT_EQ(e.field(), "--skeleton");
  EXPECT_NE(std::string(e.what()).find("'smpl' or 'humanoid'"), std::string::npos);
}

TEST(EngineRig, HumanoidGlbHasEveryRequiredUnityBoneInTheRightHierarchy) {
  const BodyModel& m = mannequin();
  GlbOptions options;
  options.skeleton = SkeletonNaming::Humanoid;
  const json doc = glb_document(write_glb(m, m.data().template_vertices, options));
  const json& nodes = doc["nodes"];
  std::map<std::string, int> node_of;
  std::map<int, int> parent_of;
  for (size_t i = 0; i < nodes.size(); ++i) {
    node_of[nodes[i].value("name", "")] = static_cast<int>(i);
    for (int c : nodes[i].value("children", std::vector<int>{})) parent_of[c] = static_cast<int>(i);
  }
  auto descends = [&](int node, int ancestor) {
    for (auto it = parent_of.find(node); it != parent_of.end(); it = parent_of.find(it->second))
      if (it->second == ancestor) return true;
    return false;
  };
  for (const auto& [bone, ancestor] : kUnityRequired) {
    ASSERT_TRUE(node_of.count(bone)) << bone << " missing";
    if (!ancestor.empty()) {
      EXPECT_TRUE(descends(node_of[bone], node_of[ancestor])) << bone << " not under " << ancestor;
    }
  }
  EXPECT_TRUE(node_of.count("Root"));
  EXPECT_TRUE(descends(node_of["Hips"], node_of["Root"]));
  for (const char* finger : {"LeftThumbDistal", "RightIndexProximal", "LeftLittleIntermediate"})
    EXPECT_TRUE(node_of.count(finger)) << finger;
  for (const auto& name : rig_joint_names()) EXPECT_FALSE(node_of.count(name)) << "SMPL name left: " << name;
}

// The real body: each bone with one child points at it, in the exported file's world frame, and
// the legs point down (Blender drew them pointing up before rest orientations were written).
TEST(EngineRig, BuiltInBodyBonesPointAtTheirChildren) {
  const BodyModel& m = mannequin();
  const Vertices& rest = m.data().template_vertices;
  const ExportRig rig = export_rig(m, m.joints(rest), rest, SkeletonNaming::Smpl);
  ASSERT_EQ(rig.size(), m.joint_count() + 1);
  std::vector<int> child_count(static_cast<size_t>(rig.size()), 0);
  for (int p : rig.parents)
    if (p >= 0) ++child_count[static_cast<size_t>(p)];
  int checked = 0;
  for (int j = 0; j < rig.size(); ++j) {
    const int p = rig.parents[static_cast<size_t>(j)];
    if (p < 0 || child_count[static_cast<size_t>(p)] != 1 || rig.model_names[static_cast<size_t>(p)] == "left_hand" ||
        rig.model_names[static_cast<size_t>(p)] == "right_hand")
      continue;
    const Eigen::Vector3d to_child = (rig.positions[static_cast<size_t>(j)] - rig.positions[static_cast<size_t>(p)]).normalized();
    EXPECT_GT(rig.orientations[static_cast<size_t>(p)].col(1).dot(to_child), 0.9999) << rig.model_names[static_cast<size_t>(p)];
    ++checked;
  }
  // root; hip, knee, ankle ×2; spine1, spine2, neck; collar, shoulder, elbow, wrist ×2; the
  // first two joints of ten fingers.
  EXPECT_EQ(checked, 1 + 6 + 3 + 8 + 20);
  auto axis = [&](const std::string& name) {
    const auto it = std::find(rig.model_names.begin(), rig.model_names.end(), name);
    return Eigen::Vector3d(rig.orientations[static_cast<size_t>(it - rig.model_names.begin())].col(1));
  };
  EXPECT_LT(axis("left_hip").y(), -0.9);
  EXPECT_LT(axis("right_knee").y(), -0.9);
  EXPECT_GT(axis("left_shoulder").x(), 0.9);   // the avatar's left is +x (it faces +z)
  EXPECT_LT(axis("right_elbow").x(), -0.9);
  EXPECT_GT(axis("left_ankle").z(), 0.5);      // the foot points forward
  EXPECT_GT(axis("spine1").y(), 0.9);
  // Rotations are proper: orthonormal with determinant 1.
  for (const auto& r : rig.orientations) {
    EXPECT_TRUE((r.transpose() * r).isIdentity(1e-12));
    EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
  }
  // The root bone stands on the floor under the pelvis.
  EXPECT_NEAR(rig.positions[static_cast<size_t>(rig.root)].y(), rest.col(1).minCoeff(), 1e-12);
  EXPECT_NEAR(rig.positions[static_cast<size_t>(rig.root)].x(), rig.positions[0].x(), 1e-12);
}

TEST(EngineRig, BadJointsAreRefused) {
  const BodyModel& m = mannequin();
  const Vertices& rest = m.data().template_vertices;
  Eigen::MatrixX3d joints = m.joints(rest);
  joints(3, 1) = std::nan("");
  EXPECT_EQ(test::catch_error([&] { export_rig(m, joints, rest, SkeletonNaming::Smpl); }).field(), "joints");
  EXPECT_EQ(test::catch_error([&] { export_rig(m, joints.topRows(5), rest, SkeletonNaming::Smpl); }).field(), "joints");
}

TEST(Provenance, BuiltInModelAllowsCommercialUseAndSaysWhereItCameFrom) {
  const Provenance p = model_provenance(mannequin());
  EXPECT_EQ(p.body_model, "mannequin-female");
  EXPECT_EQ(p.sex, "female");
  EXPECT_TRUE(p.commercial_use);
  EXPECT_NE(p.licence.find("public-domain"), std::string::npos);
  EXPECT_NE(p.model_source.find("ANSUR"), std::string::npos);
}

TEST(Provenance, UnknownOrNonCommercialLicencesRefuseCommercialUse) {
  BodyModelData d = test::toy_model().data();
  EXPECT_FALSE(model_provenance(BodyModel(d)).commercial_use);  // no licence at all
  d.metadata["licence"] = "CC BY-NC 4.0, non-commercial";
  EXPECT_FALSE(model_provenance(BodyModel(d)).commercial_use);
  d.metadata["licence"] = "CC0";
  EXPECT_TRUE(model_provenance(BodyModel(d)).commercial_use);
  d.metadata["format"] = "smpl";  // an SMPL file's licence wins whatever the metadata says
  EXPECT_FALSE(model_provenance(BodyModel(d)).commercial_use);
}

TEST(Provenance, GlbCarriesModelLicenceSexMeasurementsAndVersion) {
  const BodyModel& m = mannequin();
  AvatarBuilder builder(std::make_shared<const BodyModel>(m));
  AvatarRequest request;
  request.measurements = {{"stature", 1.65}, {"weight", 61.5}};
  request.vertex_uncertainty = false;
  const Avatar avatar = builder.build(request);
  GlbOptions options;
  options.provenance = avatar_provenance(m, avatar);
  const json doc = glb_document(write_glb(m, avatar.rest_vertices, options));
  const std::string copyright = doc["asset"]["copyright"];
  EXPECT_NE(copyright.find("mannequin-female"), std::string::npos) << copyright;
  EXPECT_NE(copyright.find("commercial use allowed"), std::string::npos) << copyright;
  const json& c = doc["asset"]["extras"]["caliper"];
  EXPECT_EQ(c["body_model"], "mannequin-female");
  EXPECT_EQ(c["sex"], "female");
  EXPECT_EQ(c["commercial_use"], true);
  EXPECT_EQ(c["regressor"], "map");
  EXPECT_EQ(c["caliper_version"], CALIPER_PROJECT_VERSION);
  EXPECT_DOUBLE_EQ(c["measurements"]["stature"]["value"].get<double>(), 165.0);
  EXPECT_EQ(c["measurements"]["stature"]["unit"], "cm");
  EXPECT_DOUBLE_EQ(c["measurements"]["weight"]["value"].get<double>(), 61.5);
  EXPECT_EQ(c["measurements"]["weight"]["unit"], "kg");
  EXPECT_EQ(c["skeleton"], "smpl");
}

TEST(Vrm, HumanoidMapMetaAndLookAt) {
  const BodyModel& m = mannequin();
  const json doc = glb_document(write_vrm(m, m.data().template_vertices));
  ASSERT_TRUE(doc.contains("extensionsUsed"));
  EXPECT_NE(std::find(doc["extensionsUsed"].begin(), doc["extensionsUsed"].end(), "VRMC_vrm"), doc["extensionsUsed"].end());
  const json& vrm = doc["extensions"]["VRMC_vrm"];
  EXPECT_EQ(vrm["specVersion"], "1.0");
  const json& bones = vrm["humanoid"]["humanBones"];
  // SMPL's one-off names land on the bone they start.
  const std::map<std::string, std::string> expected = {{"hips", "pelvis"}, {"leftUpperArm", "left_shoulder"},
      {"leftShoulder", "left_collar"}, {"leftHand", "left_wrist"}, {"leftFoot", "left_ankle"}, {"leftToes", "left_foot"},
      {"rightThumbMetacarpal", "right_thumb1"}, {"leftLittleDistal", "left_pinky3"}};
  for (const auto& [bone, joint] : expected) {
    ASSERT_TRUE(bones.contains(bone)) << bone;
    EXPECT_EQ(doc["nodes"][bones[bone]["node"].get<int>()]["name"], joint) << bone;
  }
  EXPECT_EQ(bones.size(), 22u + 30u);  // SMPL's 24 less the two knuckle joints, and 30 finger bones
  EXPECT_EQ(vrm["meta"]["licenseUrl"], "https://vrm.dev/licenses/1.0/");
  EXPECT_EQ(vrm["meta"]["commercialUsage"], "corporation");
  EXPECT_EQ(doc["nodes"][vrm["firstPerson"]["meshAnnotations"][0]["node"].get<int>()].value("mesh", -1), 0);
  const auto offset = vrm["lookAt"]["offsetFromHeadBone"].get<std::vector<double>>();
  ASSERT_EQ(offset.size(), 3u);
  // The offset is in the head bone's frame, which leans forward with the neck; in the body's
  // own frame the eyes are above the head joint (the skull's base) and in front of it.
  const Vertices& rest = m.data().template_vertices;
  const ExportRig rig = export_rig(m, m.joints(rest), rest, SkeletonNaming::Smpl);
  const int head = static_cast<int>(std::find(rig.model_names.begin(), rig.model_names.end(), "head") - rig.model_names.begin());
  ASSERT_LT(head, rig.size());
  const Eigen::Vector3d eyes = rig.orientations[static_cast<size_t>(head)] * Eigen::Vector3d(offset[0], offset[1], offset[2]);
  EXPECT_NEAR(eyes.x(), 0.0, 1e-6);
  EXPECT_GT(eyes.y(), 0.03);
  EXPECT_LT(eyes.y(), 0.15);
  EXPECT_GT(eyes.z(), 0.03);
}

TEST(Vrm, NonCommercialModelsSayPersonalNonProfitAndModelsWithoutSmplNamesAreRefused) {
  BodyModelData d = test::toy_model().data();
  d.metadata["licence"] = "non-commercial research licence";
  const BodyModel toy(d);
  const json doc = glb_document(write_vrm(toy, toy.data().template_vertices));
  EXPECT_EQ(doc["extensions"]["VRMC_vrm"]["meta"]["commercialUsage"], "personalNonProfit");
  EXPECT_EQ(doc["extensions"]["VRMC_vrm"]["meta"]["allowRedistribution"], false);
  d.joint_names[0] = "root_joint";
  const BodyModel renamed(d);
  const Error e = test::catch_error([&] { write_vrm(renamed, renamed.data().template_vertices); });
  EXPECT_EQ(e.kind(), ErrorKind::Unsupported);
  EXPECT_EQ(e.field(), "hips");
}

// The avatar's files: a format by name or by a path's ending (any case), the one rule for which
// carry morph targets, and the refusal naming the caller's field.
TEST(AvatarFiles, FormatsByNameAndEndingAndWhichCarryMorphs) {
  EXPECT_EQ(avatar_format_named("FBX"), AvatarFormat::Fbx);
  EXPECT_EQ(avatar_format_named("stl"), std::nullopt);
  EXPECT_EQ(avatar_file_format("out.glb/me.Vrm", "--output"), AvatarFormat::Vrm);
  EXPECT_EQ(test::catch_error([] { avatar_file_format("out.glb/me", "--output"); }).field(), "--output");
  EXPECT_TRUE(is_avatar_file_name("ME.OBJ"));
  EXPECT_FALSE(is_avatar_file_name("me.obj.png"));
  for (AvatarFormat f : {AvatarFormat::Glb, AvatarFormat::Vrm, AvatarFormat::Fbx}) EXPECT_TRUE(avatar_format_carries_morphs(f));
  EXPECT_FALSE(avatar_format_carries_morphs(AvatarFormat::Obj));
  AvatarFileOptions morphs;
  morphs.morphs = true;
  check_avatar_file_options(AvatarFormat::Fbx, morphs, "--morphs");  // no throw
  check_avatar_file_options(AvatarFormat::Obj, {}, "--morphs");
  const Error e = test::catch_error([&] { check_avatar_file_options(AvatarFormat::Obj, morphs, "--morphs"); });
  EXPECT_EQ(e.field(), "--morphs");
  EXPECT_NE(std::string(e.what()).find("only .glb, .vrm, .fbx"), std::string::npos) << e.what();
  const BodyModel& m = mannequin();
  Avatar avatar;
  avatar.rest_vertices = m.data().template_vertices;
  EXPECT_EQ(test::catch_error([&] { write_avatar(AvatarFormat::Obj, m, avatar, morphs); }).field(), "morphs");
  EXPECT_EQ(write_avatar(AvatarFormat::Obj, m, avatar).rfind("# Caliper avatar", 0), 0u);
}

// docs/engines.md's mapping table says what the code does: each row's SMPL, humanoid and VRM
// names are one row of humanoid_bone_table(), and the left side and SMPL's trunk are all there.
TEST(HumanoidNames, TheDocumentedTableMatchesTheCode) {
  std::ifstream in(std::string(CALIPER_SOURCE_DIR) + "/docs/engines.md");
  ASSERT_TRUE(in) << "docs/engines.md not found";
  std::set<std::string> documented;
  bool in_table = false;  // from the table's header to the blank line after it
  for (std::string line; std::getline(in, line);) {
    if (line.find("| SMPL (`--skeleton smpl`)") == 0) in_table = true;
    if (line.empty()) in_table = false;
    if (!in_table || line.rfind("| `", 0) != 0) continue;
    std::vector<std::string> cells;
    for (size_t at = 1, bar; (bar = line.find('|', at)) != std::string::npos; at = bar + 1) {
      std::string c = line.substr(at, bar - at);
      c.erase(0, c.find_first_not_of(' '));
      c.erase(c.find_last_not_of(' ') + 1);
      cells.push_back(c);
    }
    if (cells.size() < 3) continue;
    auto unquote = [](const std::string& c) { return c.size() > 2 && c.front() == '`' ? c.substr(1, c.find('`', 1) - 1) : std::string(); };
    const std::string smpl = unquote(cells[0]);
    const HumanoidBone* b = find_humanoid_bone(smpl);
    ASSERT_NE(b, nullptr) << line;
    EXPECT_EQ(unquote(cells[1]), b->humanoid) << line;
    EXPECT_EQ(unquote(cells[2]), b->vrm) << line;
    documented.insert(smpl);
  }
  for (const auto& name : rig_joint_names()) {
    if (name.rfind("right_", 0) != 0) {
      EXPECT_TRUE(documented.count(name)) << name << " is not in docs/engines.md";
    }
  }
}

// ---- Unity and Unreal: their documented import requirements, on a built avatar's FBX ----------
// Neither engine runs here. Each test checks one requirement their documentation states that a
// file can be checked against mechanically, on the file `caliper avatar --sex female --height 165
// --weight 61.5 --skeleton humanoid --morphs -o me.fbx` writes, read back by Assimp (an independent
// reader). docs/engines.md lists what is and is not covered.
#ifdef CALIPER_HAVE_ASSIMP
namespace {

struct EngineFbx {
  std::string bytes;
  Assimp::Importer importer;
  const aiScene* scene = nullptr;

  EngineFbx() {
    const BodyModel& m = mannequin();
    AvatarBuilder builder(std::make_shared<const BodyModel>(m));
    AvatarRequest request;
    request.measurements = {{"stature", 1.65}, {"weight", 61.5}};
    request.vertex_uncertainty = false;
    AvatarFileOptions file;
    file.skeleton = SkeletonNaming::Humanoid;
    file.morphs = true;
    bytes = write_avatar(AvatarFormat::Fbx, m, builder.build(request), file);
    scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), aiProcess_ValidateDataStructure, "fbx");
    // Assimp keeps the file's numbers; the file declares how many centimetres one unit is.
    double cm = 0;
    float cm_f = 0;  // Assimp keeps FBX doubles as float or double depending on the version
    if (scene && scene->mMetaData && !scene->mMetaData->Get("UnitScaleFactor", cm) && scene->mMetaData->Get("UnitScaleFactor", cm_f)) cm = cm_f;
    metres_per_unit = cm / 100.0;
  }
  double metres_per_unit = 0;
  const aiNode* node(const std::string& name) const { return scene->mRootNode->FindNode(name.c_str()); }
  // A node's rest position in the file's frame, in metres by the declared unit.
  Eigen::Vector3d at(const std::string& name) const {
    aiMatrix4x4 world;
    for (const aiNode* n = node(name); n; n = n->mParent) world = n->mTransformation * world;
    return metres_per_unit * Eigen::Vector3d(world.a4, world.b4, world.c4);
  }
};

const EngineFbx& engine_fbx() {
  static const EngineFbx f;
  return f;
}

#define REQUIRE_ENGINE_FBX()                                                                   \
  const EngineFbx& fbx = engine_fbx();                                                        \
  ASSERT_NE(fbx.scene, nullptr) << fbx.importer.GetErrorString();                              \
  ASSERT_EQ(fbx.scene->mNumMeshes, 1u)

double degrees_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

}  // namespace

// Unity's Humanoid rig ("Configuring the Avatar"): every required bone matched, in the
// predefined structure. The auto-mapper matches Unity's own HumanBodyBones names first.
TEST(UnityRequirements, FbxHasEveryRequiredHumanoidBoneUnderItsParent) {
  REQUIRE_ENGINE_FBX();
  for (const auto& [bone, ancestor] : kUnityRequired) {
    const aiNode* n = fbx.node(bone);
    ASSERT_NE(n, nullptr) << bone << " missing";
    if (ancestor.empty()) continue;
    bool found = false;
    for (const aiNode* up = n->mParent; up && !found; up = up->mParent) found = ancestor == up->mName.C_Str();
    EXPECT_TRUE(found) << bone << " is not under " << ancestor;
  }
}

// "…and that the model is in T-pose": arms straight out sideways, legs straight down, facing
// the file's front (+Z), standing on the floor.
TEST(UnityRequirements, FbxStandsInATPoseFacingItsFrontOnTheFloor) {
  REQUIRE_ENGINE_FBX();
  const Eigen::Vector3d left(1, 0, 0), down(0, -1, 0), front(0, 0, 1);
  EXPECT_LT(degrees_between(fbx.at("LeftHand") - fbx.at("LeftUpperArm"), left), 10.0);
  EXPECT_LT(degrees_between(fbx.at("RightHand") - fbx.at("RightUpperArm"), -left), 10.0);
  EXPECT_LT(degrees_between(fbx.at("LeftFoot") - fbx.at("LeftUpperLeg"), down), 10.0);
  EXPECT_LT(degrees_between(fbx.at("RightFoot") - fbx.at("RightUpperLeg"), down), 10.0);
  EXPECT_LT(degrees_between(fbx.at("LeftToes") - fbx.at("LeftFoot"), front), 60.0);
  const aiMesh* mesh = fbx.scene->mMeshes[0];
  float lowest = 1e9f, highest = -1e9f;
  for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
    lowest = std::min(lowest, mesh->mVertices[v].y);
    highest = std::max(highest, mesh->mVertices[v].y);
  }
  EXPECT_NEAR(lowest * fbx.metres_per_unit, 0.0, 1e-3);
  EXPECT_NEAR((highest - lowest) * fbx.metres_per_unit, 1.65, 0.01);  // the stature asked for, by the declared unit
}

// Units and axes are declared: centimetres, so Unreal (which takes the numbers as centimetres
// unless Convert Scene Unit is ticked) gets the true size as it is, and Unity's Convert Units
// (file scale 0.01, on by default) gives 1 unit = 1 m; Convert Scene turns +Y up into Unreal's Z up.
TEST(UnityRequirements, FbxDeclaresCentimetresYUpAndZFront) {
  REQUIRE_ENGINE_FBX();
  ASSERT_NE(fbx.scene->mMetaData, nullptr);
  double scale = 0;
  float scale_f = 0;  // Assimp keeps FBX doubles as float or double depending on the version
  if (!fbx.scene->mMetaData->Get("UnitScaleFactor", scale) && fbx.scene->mMetaData->Get("UnitScaleFactor", scale_f)) scale = scale_f;
  EXPECT_EQ(scale, 1.0);  // centimetres per file unit
  const std::map<std::string, int> axes = {{"UpAxis", 1},    {"UpAxisSign", 1}, {"FrontAxis", 2},
                                           {"FrontAxisSign", 1}, {"CoordAxis", 0}, {"CoordAxisSign", 1}};
  for (const auto& [key, expected] : axes) {
    int value = -9;
    EXPECT_TRUE(fbx.scene->mMetaData->Get(key.c_str(), value)) << key;
    EXPECT_EQ(value, expected) << key;
  }
}

// Unity's standard skin import keeps 4 bones per vertex (ModelImporterSkinWeights.Standard);
// Unreal takes up to 8 (12 in Unreal 5). Every vertex's weights sum to 1.
TEST(UnityRequirements, FbxSkinHasAtMostFourNormalisedInfluencesPerVertex) {
  REQUIRE_ENGINE_FBX();
  const aiMesh* mesh = fbx.scene->mMeshes[0];
  std::vector<int> count(mesh->mNumVertices, 0);
  std::vector<double> sum(mesh->mNumVertices, 0.0);
  for (unsigned b = 0; b < mesh->mNumBones; ++b)
    for (unsigned k = 0; k < mesh->mBones[b]->mNumWeights; ++k) {
      const aiVertexWeight& w = mesh->mBones[b]->mWeights[k];
      ++count[w.mVertexId];
      sum[w.mVertexId] += w.mWeight;
    }
  EXPECT_LE(*std::max_element(count.begin(), count.end()), 4);
  EXPECT_GE(*std::min_element(count.begin(), count.end()), 1);
  for (unsigned v = 0; v < mesh->mNumVertices; ++v) ASSERT_NEAR(sum[v], 1.0, 1e-5) << "vertex " << v;
}

// Unreal's FBX importer refuses a skeleton with several roots ("Multiple roots are found in the
// bone hierarchy. We only support single root bone."): every bone descends from one, Root, on
// the floor under the hips.
TEST(UnrealRequirements, FbxSkeletonHasOneRootBoneOnTheFloorUnderTheHips) {
  REQUIRE_ENGINE_FBX();
  const ExportRig rig = export_rig(mannequin(), mannequin().joints(mannequin().data().template_vertices),
                                   mannequin().data().template_vertices, SkeletonNaming::Humanoid);
  const std::set<std::string> bones(rig.names.begin(), rig.names.end());
  std::set<std::string> roots;
  for (const auto& name : bones) {
    const aiNode* n = fbx.node(name);
    ASSERT_NE(n, nullptr) << name;
    if (!n->mParent || !bones.count(n->mParent->mName.C_Str())) roots.insert(name);
  }
  EXPECT_EQ(roots, std::set<std::string>{"Root"});
  EXPECT_NEAR(fbx.at("Root").y(), 0.0, 1e-3);
  EXPECT_NEAR(fbx.at("Root").x(), fbx.at("Hips").x(), 1e-9);
  EXPECT_NEAR(fbx.at("Root").z(), fbx.at("Hips").z(), 1e-9);
}

// Unreal builds the reference pose from the file's bind pose and warns when the skin's bind
// matrices disagree with the skeleton: each bone's inverse bind (Assimp's offset matrix, from
// the cluster) undoes its rest transform in the node tree, and the file has a BindPose.
TEST(UnrealRequirements, FbxBindPoseIsTheSkeletonsRestPose) {
  REQUIRE_ENGINE_FBX();
  const aiMesh* mesh = fbx.scene->mMeshes[0];
  ASSERT_GE(mesh->mNumBones, 50u);
  for (unsigned b = 0; b < mesh->mNumBones; ++b) {
    const aiBone* bone = mesh->mBones[b];
    aiMatrix4x4 world;
    for (const aiNode* n = fbx.node(bone->mName.C_Str()); n; n = n->mParent) world = n->mTransformation * world;
    const aiMatrix4x4 product = bone->mOffsetMatrix * world;
    // Assimp's matrices are single precision: rotations to 1e-5, translations (in metres) to 10 µm.
    for (unsigned r = 0; r < 4; ++r)
      for (unsigned c = 0; c < 4; ++c) {
        const double scale = c == 3 && r < 3 ? fbx.metres_per_unit : 1.0;
        EXPECT_NEAR(product[r][c] * scale, r == c ? 1.0 : 0.0, 1e-5) << bone->mName.C_Str();
      }
  }
  EXPECT_NE(fbx.bytes.find("BindPose"), std::string::npos);
}

// Unreal's Import Morph Targets and Unity's Import BlendShapes read FBX blend shapes: one per
// shape direction of the model, named shape_k.
TEST(UnrealRequirements, FbxBlendShapesAreOnePerShapeDirection) {
  REQUIRE_ENGINE_FBX();
  const aiMesh* mesh = fbx.scene->mMeshes[0];
  ASSERT_EQ(mesh->mNumAnimMeshes, static_cast<unsigned>(mannequin().shape_count()));
  std::set<std::string> names;
  for (unsigned a = 0; a < mesh->mNumAnimMeshes; ++a) names.insert(mesh->mAnimMeshes[a]->mName.C_Str());
  for (int k = 0; k < mannequin().shape_count(); ++k) EXPECT_TRUE(names.count("shape_" + std::to_string(k))) << k;
}
#else
TEST(UnityRequirements, FbxHasEveryRequiredHumanoidBoneUnderItsParent) {
  FAIL() << "built without Assimp: install libassimp-dev (scripts/install-deps.sh)";
}
#endif
