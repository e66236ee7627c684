// The desktop tool's JSON API without the network: routes, good and bad requests, exports,
// measurement sets, static-file resolution. The body is the unit tests' toy prism (every
// coordinate linear in β), so answers are exact: R2 must reproduce stature, the mesh's top must
// sit at the reported stature, the topology must be the model's faces.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <thread>

#include "api_calls.h"
#include "caliper/caliper.h"
#include "static_files.h"

namespace caliper::server {
namespace {

using nlohmann::json;
using test_calls::expect_error;

std::vector<unsigned char> unbase64(const std::string& text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<unsigned char> out;
  unsigned buffer = 0;
  int bits = 0;
  for (char c : text) {
    const int v = value(c);
    if (v < 0) continue;  // '=' padding
    buffer = (buffer << 6) | unsigned(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((buffer >> bits) & 0xff));
    }
  }
  return out;
}

class ApiTest : public ::testing::Test {
 protected:
  static Api& api() {
    static Api a([] {
      ApiOptions o;
      o.models_dir = test::toy_models_dir();
      o.default_model = "toy";
      return o;
    }());
    return a;
  }
  static ApiResponse call(const std::string& method, const std::string& path, const std::string& body = {},
                          std::map<std::string, std::string> query = {}, const std::string& content_type = "application/json") {
    ApiRequest r;
    r.method = method;
    r.path = path;
    r.body = body;
    r.query = std::move(query);
    r.content_type = content_type;
    return api().handle(r);
  }
  static json post(const std::string& path, const json& body, int expected_status = 200) {
    ApiResponse r = call("POST", path, body.dump());
    EXPECT_EQ(r.status, expected_status) << r.body;
    return json::parse(r.body);
  }
  static json avatar_body(double stature, double weight, const std::string& regressor = "R2") {
    return {{"sex", "female"}, {"model", "toy"}, {"regressor", regressor}, {"measurements", {{"stature", stature}, {"weight", weight}}}};
  }
};

TEST_F(ApiTest, ModelsListsFamiliesWithTheirSexesAndThePresets) {
  ApiResponse r = call("GET", "/api/models");
  ASSERT_EQ(r.status, 200);
  json j = json::parse(r.body);
  EXPECT_EQ(j["default_model"], "toy");
  ASSERT_EQ(j["models"].size(), 1u);
  EXPECT_EQ(j["models"][0]["name"], "toy");
  EXPECT_EQ(j["models"][0]["sexes"], json({"female", "male"}));
  std::vector<std::string> names;
  for (const auto& reg : j["regressors"]) names.push_back(reg["name"]);
  EXPECT_EQ(names, (std::vector<std::string>{"R2", "R4", "R5", "R6", "auto", "map"}));
  EXPECT_EQ(j["regressors"][0]["inputs"], json({"stature", "weight"}));
}

TEST_F(ApiTest, MeasurementCatalogueHasRangesUnitsAndThePapersHierarchy) {
  ApiResponse r = call("GET", "/api/measurements");
  ASSERT_EQ(r.status, 200);
  json j = json::parse(r.body);
  EXPECT_EQ(j["hierarchy"], json::parse(R"([["stature","weight"],["span","crotch_height"],["hip_breadth","arm_length"]])"));
  EXPECT_EQ(j["measurements"].size(), measurement_catalogue().size());
  int inputs = 0;
  for (const auto& m : j["measurements"]) {
    const MeasurementInfo* info = find_measurement_info(m["name"]);
    ASSERT_NE(info, nullptr);
    EXPECT_EQ(m["unit"], edge_unit(*info));
    EXPECT_EQ(m["accepted_range"]["min"], info->min_edge);
    EXPECT_EQ(m["accepted_range"]["max"], info->max_edge);
    if (m["input"].is_null()) continue;
    ++inputs;
    // Sliders lie inside what the API accepts, and the starting values on the sliders.
    const auto& s = m["input"]["slider"];
    EXPECT_GE(s["min"].get<double>(), info->min_edge) << m["name"];
    EXPECT_LE(s["max"].get<double>(), info->max_edge) << m["name"];
    for (const char* sex : {"female", "male", "neutral"}) {
      const double d = m["input"]["default"][sex];
      EXPECT_GE(d, s["min"].get<double>()) << m["name"] << " " << sex;
      EXPECT_LE(d, s["max"].get<double>()) << m["name"] << " " << sex;
    }
  }
  EXPECT_EQ(inputs, 6);
}

TEST_F(ApiTest, AvatarReproducesItsInputsAndTheMeshMatchesTheReport) {
  json j = post("/api/avatar", avatar_body(172.0, 70.0));
  const json& report = j["report"];
  EXPECT_EQ(report["regressor"], "R2");
  EXPECT_EQ(report["inputs"], json({"stature", "weight"}));
  // Stature is linear in β on the toy body, so the least-squares regressor reproduces it exactly.
  EXPECT_NEAR(report["measurements"]["stature"]["achieved_cm"].get<double>(), 172.0, 0.01);
  EXPECT_NEAR(report["measurements"]["stature"]["requested_cm"].get<double>(), 172.0, 1e-9);
  EXPECT_EQ(report["beta"].size(), 3u);
  EXPECT_TRUE(report["plausibility"]["verdict"].is_string());
  // The mesh: N×3 float32; its top vertex is the stature above the floor (feet on y = 0).
  const int n = j["mesh"]["vertex_count"];
  const auto bytes = unbase64(j["mesh"]["positions"]);
  ASSERT_EQ(bytes.size(), size_t(n) * 3 * sizeof(float));
  std::vector<float> p(size_t(n) * 3);
  std::memcpy(p.data(), bytes.data(), bytes.size());
  float top = -1e9f, bottom = 1e9f;
  for (int i = 0; i < n; ++i) {
    top = std::max(top, p[size_t(i) * 3 + 1]);
    bottom = std::min(bottom, p[size_t(i) * 3 + 1]);
  }
  EXPECT_NEAR((top - bottom) * 100.0, report["measurements"]["stature"]["achieved_cm"].get<double>(), 1e-3);
  EXPECT_EQ(j["mesh"]["topology"], "/api/topology?model=toy&sex=female");
  EXPECT_GE(j["timing_ms"]["total"].get<double>(), 0.0);
}

TEST_F(ApiTest, ATallerRequestGivesATallerMesh) {
  json a = post("/api/avatar", avatar_body(160.0, 60.0));
  json b = post("/api/avatar", avatar_body(180.0, 60.0));
  EXPECT_NE(a["mesh"]["positions"], b["mesh"]["positions"]);
  EXPECT_NEAR(b["report"]["measurements"]["stature"]["achieved_cm"].get<double>() -
                  a["report"]["measurements"]["stature"]["achieved_cm"].get<double>(), 20.0, 0.02);
}

TEST_F(ApiTest, AutoUsesEveryGivenValueAndMeshCanBeLeftOut) {
  json body = avatar_body(170, 65, "auto");
  body["measurements"]["span"] = 172;
  body["measurements"]["inseam"] = 80;  // an alias
  body["mesh"] = false;
  json j = post("/api/avatar", body);
  EXPECT_EQ(j["report"]["regressor"], "map");
  EXPECT_EQ(j["report"]["inputs"].size(), 4u);
  EXPECT_FALSE(j.contains("mesh"));
  EXPECT_NEAR(j["report"]["measurements"]["crotch_height"]["requested_cm"].get<double>(), 80.0, 1e-9);
}

// The map estimator through the API: on the toy body stature is linear in β, so with
// "exact" noise it is reproduced; the report carries per-measurement SDs and the mesh the
// per-vertex SDs (N float32, finite, ≥ 0, and > 0 at the top, which moves with β).
TEST_F(ApiTest, MapReturnsTheUncertainty) {
  json body = avatar_body(175.0, 70.0, "map");
  body["noise"] = "exact";
  json j = post("/api/avatar", body);
  const json& report = j["report"];
  EXPECT_EQ(report["regressor"], "map");
  EXPECT_EQ(report["inputs"], json({"stature", "weight"}));
  EXPECT_NEAR(report["measurements"]["stature"]["achieved_cm"].get<double>(), 175.0, 0.05);
  EXPECT_EQ(report["uncertainty"]["noise"], "exact");
  EXPECT_GE(report["measurements"]["stature"]["uncertainty_cm"].get<double>(), 0.0);
  EXPECT_LT(report["measurements"]["stature"]["uncertainty_cm"].get<double>(), 0.05);
  EXPECT_TRUE(report["warnings"].is_array());
  const int n = j["mesh"]["vertex_count"];
  const auto bytes = unbase64(j["mesh"]["vertex_sd"]);
  ASSERT_EQ(bytes.size(), size_t(n) * sizeof(float));
  std::vector<float> sd(static_cast<size_t>(n));
  std::memcpy(sd.data(), bytes.data(), bytes.size());
  for (float v : sd) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
  EXPECT_GT(*std::max_element(sd.begin(), sd.end()), 0.0f);
  // "self" noise: stature's SD is then larger than with exact values, and a noise_sd override
  // for stature (cm) makes it larger still.
  body["noise"] = "self";
  const double self_sd = post("/api/avatar", body)["report"]["measurements"]["stature"]["uncertainty_cm"];
  EXPECT_GT(self_sd, report["measurements"]["stature"]["uncertainty_cm"].get<double>());
  body["noise_sd"] = {{"height", 5.0}};
  const double loose_sd = post("/api/avatar", body)["report"]["measurements"]["stature"]["uncertainty_cm"];
  EXPECT_GT(loose_sd, self_sd);
  // Regressors other than map carry no uncertainty.
  json r2 = post("/api/avatar", avatar_body(175.0, 70.0, "R2"));
  EXPECT_FALSE(r2["report"].contains("uncertainty"));
  EXPECT_FALSE(r2["mesh"].contains("vertex_sd"));
}

TEST_F(ApiTest, MapRefusesBadNoiseSettings) {
  json body = avatar_body(170.0, 65.0, "map");
  body["noise"] = "sloppy";
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "noise");
  body["noise"] = "self";
  body["noise_sd"] = {{"stature", -1}};
  // The field is the SD, not stature itself: no accepted range of statures beside a message
  // about SDs.
  const json e = expect_error(call("POST", "/api/avatar", body.dump()), 400, "noise_sd.stature");
  EXPECT_TRUE(e["accepted_range"].is_null()) << e.dump();
  body["noise_sd"] = {{"chest_circumference", 2}};  // a SD for a value that was not given
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "chest_circumference");
  body["noise_sd"] = json::array({1});
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "noise_sd");
}

TEST_F(ApiTest, TopologyIsTheModelsFaces) {
  ApiResponse r = call("GET", "/api/topology", {}, {{"model", "toy"}, {"sex", "male"}});
  ASSERT_EQ(r.status, 200) << r.body;
  json j = json::parse(r.body);
  const BodyModel m = load_model(test::toy_models_dir() + "/toy-male.npz", Sex::Male);
  ASSERT_EQ(j["face_count"], m.face_count());
  EXPECT_EQ(j["vertex_count"], m.vertex_count());
  const auto bytes = unbase64(j["faces"]);
  ASSERT_EQ(bytes.size(), size_t(m.face_count()) * 3 * 4);
  std::vector<std::uint32_t> f(size_t(m.face_count()) * 3);
  std::memcpy(f.data(), bytes.data(), bytes.size());
  for (int i = 0; i < m.face_count(); ++i)
    for (int c = 0; c < 3; ++c) ASSERT_EQ(f[size_t(i) * 3 + c], std::uint32_t(m.faces()(i, c))) << "face " << i;
  EXPECT_EQ(j["joint_names"].size(), 24u);
}

TEST_F(ApiTest, BadValuesNameTheFieldAndTheAcceptedRange) {
  json forced = avatar_body(1700, 60);
  forced["force"] = true;  // as typed: then the range decides
  json e = expect_error(call("POST", "/api/avatar", forced.dump()), 400, "stature");
  EXPECT_EQ(e["accepted_range"], json({{"min", 50.0}, {"max", 250.0}, {"unit", "cm"}}));
  EXPECT_EQ(e["kind"], "out_of_range");
  e = expect_error(call("POST", "/api/avatar", avatar_body(170, -3).dump()), 400, "weight");
  EXPECT_EQ(e["accepted_range"]["unit"], "kg");
  EXPECT_EQ(e["accepted_range"]["min"], 10.0);
  json body = avatar_body(170, 60);
  body["measurements"]["stature"] = "tall";
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "stature");
  body = avatar_body(170, 60);
  body["measurements"]["hip_width"] = 1e308 * 10;  // serialised as null by JSON: skipped, still fine
  EXPECT_EQ(call("POST", "/api/avatar", body.dump()).status, 200);
  // A literal the JSON grammar does not have.
  expect_error(call("POST", "/api/avatar", R"({"measurements": {"stature": NaN, "weight": 60}})"), 400, "body");
  body = avatar_body(170, 60);
  body["measurements"]["shoe_size"] = 42;
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "shoe_size");
  body = avatar_body(170, 60);
  body["measurements"]["height"] = 171;  // stature given twice
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "stature");
}

TEST_F(ApiTest, BadRequestsAreRefusedWithJsonErrors) {
  expect_error(call("POST", "/api/avatar", "{not json"), 400, "body");
  expect_error(call("POST", "/api/avatar", ""), 400, "body");
  expect_error(call("POST", "/api/avatar", "[1,2]"), 400, "body");
  expect_error(call("POST", "/api/avatar", R"({"sex":"female"})"), 400, "measurements");
  json body = avatar_body(170, 60);
  body["sex"] = "robot";
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "sex");
  body = avatar_body(170, 60);
  body["model"] = "mannequin-that-is-not-here";
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "model");
  body["model"] = "../models/toy-female";  // names only, never paths
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "model");
  body["model"] = test::toy_models_dir() + "/toy-female.npz";
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "model");
  body = avatar_body(170, 60, "R7");
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "regressor");
  body = avatar_body(170, 60);
  body["colour"] = "blue";
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "colour");
  // A valid request the regressor cannot serve: R5 needs hip breadth.
  json e = expect_error(call("POST", "/api/avatar", avatar_body(170, 60, "R5").dump()), 422, "span");
  EXPECT_EQ(e["kind"], "unsupported");
  expect_error(call("GET", "/api/nothing-here"), 404, "path");
  expect_error(call("GET", "/api/avatar"), 405, "method");
  expect_error(call("GET", "/api/topology", {}, {{"model", "toy"}, {"sex", "alien"}}), 400, "sex");
}

// nlohmann refuses 1e999 with an out_of_range exception, not a parse error; it is still the
// client's mistake (400), on every endpoint that reads a JSON body.
TEST_F(ApiTest, NumbersTooLargeForADoubleAreA400NamingTheBody) {
  const std::string huge = R"({"sex":"female","measurements":{"stature":1e999,"weight":60}})";
  for (const char* path : {"/api/avatar", "/api/export/glb", "/api/export/fbx", "/api/export/obj", "/api/export/report",
                           "/api/measurement-set/import", "/api/measurement-set/export"}) {
    json e = expect_error(call("POST", path, huge), 400, "body");
    EXPECT_EQ(e["kind"], "invalid_argument") << path;
    EXPECT_NE(e["message"].get<std::string>().find("too large"), std::string::npos) << path << ": " << e;
  }
  // A huge integer literal (no exponent) overflows the same way.
  json e = expect_error(call("POST", "/api/measurement-set/import", "{\"stature\": 1" + std::string(400, '0') + "}"), 400, "body");
  EXPECT_EQ(e["kind"], "invalid_argument");
}

// The list in the message is the fields the endpoint takes: mesh on /api/avatar, not on exports.
// "morphs": true puts the model's shape directions into the rigged exports, one target each; an
// OBJ cannot hold them and says which files can.
TEST_F(ApiTest, ExportsCarryMorphTargetsWhenAsked) {
  const int shapes = load_model(test::toy_models_dir() + "/toy-female.npz", Sex::Female).shape_count();
  ASSERT_GT(shapes, 0);
  json body = avatar_body(168, 62);
  auto glb_targets = [&](const std::string& kind) {
    const ApiResponse r = call("POST", "/api/export/" + kind, body.dump());
    EXPECT_EQ(r.status, 200) << r.body;
    std::uint32_t length = 0;
    std::memcpy(&length, r.body.data() + 12, 4);
    const json mesh = json::parse(r.body.substr(20, length))["meshes"][0];
    return mesh["primitives"][0].value("targets", json::array()).size();
  };
  auto fbx_channels = [&] {
    const ApiResponse r = call("POST", "/api/export/fbx", body.dump());
    EXPECT_EQ(r.status, 200) << r.body;
    size_t count = 0;
    for (size_t at = r.body.find("BlendShapeChannel"); at != std::string::npos; at = r.body.find("BlendShapeChannel", at + 1)) ++count;
    return count;
  };
  EXPECT_EQ(glb_targets("glb"), 0u);
  EXPECT_EQ(fbx_channels(), 0u);
  body["morphs"] = true;
  EXPECT_EQ(glb_targets("glb"), static_cast<size_t>(shapes));
  EXPECT_EQ(glb_targets("vrm"), static_cast<size_t>(shapes));
  EXPECT_EQ(fbx_channels(), static_cast<size_t>(shapes));
  const json e = expect_error(call("POST", "/api/export/obj", body.dump()), 400, "morphs");
  EXPECT_NE(e["message"].get<std::string>().find(".glb, .vrm, .fbx"), std::string::npos) << e;
  body["morphs"] = "yes";
  expect_error(call("POST", "/api/export/glb", body.dump()), 400, "morphs");
}

TEST_F(ApiTest, UnknownFieldMessagesListWhatTheEndpointAccepts) {
  json body = avatar_body(170, 60);
  body["colour"] = "blue";
  json e = expect_error(call("POST", "/api/avatar", body.dump()), 400, "colour");
  EXPECT_NE(e["message"].get<std::string>().find("sex, model, regressor, measurements, mesh, pose, noise, noise_sd, force"), std::string::npos) << e;
  body = avatar_body(170, 60);
  body["mesh"] = false;
  EXPECT_EQ(call("POST", "/api/avatar", body.dump()).status, 200);
  e = expect_error(call("POST", "/api/export/obj", body.dump()), 400, "mesh");
  EXPECT_NE(e["message"].get<std::string>().find("sex, model, regressor, measurements, noise, noise_sd, force, skeleton, morphs)"), std::string::npos) << e;
}

// The viewer's pose: t (the default, the rest pose), a or stride on /api/avatar; anything else is
// a 400 naming "pose"; exports take no pose (they are rigged, in the rest pose).
TEST_F(ApiTest, AvatarPoseIsCheckedAndEchoed) {
  json body = avatar_body(170, 60);
  const json rest = post("/api/avatar", body);
  EXPECT_EQ(rest["mesh"]["pose"], "t");
  body["pose"] = "T";
  const json t = post("/api/avatar", body);
  EXPECT_EQ(t["mesh"]["pose"], "t");
  EXPECT_EQ(t["mesh"]["positions"], rest["mesh"]["positions"]);
  for (const char* pose : {"a", "stride"}) {
    body["pose"] = pose;
    const json posed = post("/api/avatar", body);
    EXPECT_EQ(posed["mesh"]["pose"], pose);
    EXPECT_EQ(posed["mesh"]["vertex_count"], rest["mesh"]["vertex_count"]);
    EXPECT_EQ(posed["report"]["measurements"], rest["report"]["measurements"]) << "a pose changes the view, not the body";
  }
  body["pose"] = "sitting";
  json e = expect_error(call("POST", "/api/avatar", body.dump()), 400, "pose");
  EXPECT_NE(e["message"].get<std::string>().find("t (the rest pose), a or stride"), std::string::npos) << e;
  body["pose"] = 3;
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "pose");
  body["pose"] = "a";
  expect_error(call("POST", "/api/export/glb", body.dump()), 400, "pose");
}

// docs/api.md: an invalid noise is refused whatever the regressor; a valid one only matters to map.
TEST_F(ApiTest, InvalidNoiseIsRefusedEvenWhenTheRegressorIgnoresIt) {
  json body = avatar_body(170, 60, "R2");
  body["noise"] = "bogus";
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "noise");
  body["noise"] = "other";
  json a = post("/api/avatar", body);
  body["noise"] = "exact";
  json b = post("/api/avatar", body);
  EXPECT_EQ(a["mesh"]["positions"], b["mesh"]["positions"]);
}

// `caliper serve --model` is checked with this before the server starts (cmd_serve.cpp).
TEST_F(ApiTest, RequireKnownModelListsTheModelsFound) {
  ApiOptions o;
  o.models_dir = test::toy_models_dir();
  EXPECT_NO_THROW(require_known_model(o, "toy"));
  try {
    require_known_model(o, "nope");
    ADD_FAILURE() << "an unknown model was accepted";
  } catch (const Error& err) {
    EXPECT_EQ(err.kind(), ErrorKind::InvalidArgument);
    EXPECT_EQ(err.field(), "model");
    const std::string m = err.what();
    EXPECT_NE(m.find("'nope'"), std::string::npos) << m;
    EXPECT_NE(m.find("available: toy"), std::string::npos) << m;
  }
  EXPECT_THROW(require_known_model(o, "../models/toy-female"), Error);  // names only, never paths
}

TEST_F(ApiTest, ExportsAreTheFilesTheyClaimToBe) {
  const json body = avatar_body(168, 62);
  ApiResponse glb = call("POST", "/api/export/glb", body.dump());
  ASSERT_EQ(glb.status, 200) << glb.body;
  EXPECT_EQ(glb.content_type, "model/gltf-binary");
  ASSERT_GE(glb.body.size(), 12u);
  EXPECT_EQ(glb.body.substr(0, 4), "glTF");
  std::uint32_t version = 0, length = 0;
  std::memcpy(&version, glb.body.data() + 4, 4);
  std::memcpy(&length, glb.body.data() + 8, 4);
  EXPECT_EQ(version, 2u);
  EXPECT_EQ(length, glb.body.size());
  EXPECT_EQ(glb.download_name.substr(glb.download_name.size() - 4), ".glb");

  ApiResponse obj = call("POST", "/api/export/obj", body.dump());
  ASSERT_EQ(obj.status, 200);
  const BodyModel m = load_model(test::toy_models_dir() + "/toy-female.npz", Sex::Female);
  int v = 0, f = 0;
  std::istringstream lines(obj.body);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("v ", 0) == 0) ++v;
    if (line.rfind("f ", 0) == 0) ++f;
  }
  EXPECT_EQ(v, m.vertex_count());
  EXPECT_EQ(f, m.face_count());

  ApiResponse report = call("POST", "/api/export/report", body.dump());
  ASSERT_EQ(report.status, 200);
  json r = json::parse(report.body);
  EXPECT_EQ(r["regressor"], "R2");
  EXPECT_NEAR(r["measurements"]["stature"]["requested_cm"].get<double>(), 168.0, 1e-9);
  // Exports take no "mesh" flag; bad values are refused as for /api/avatar.
  expect_error(call("POST", "/api/export/glb", avatar_body(9999, 60).dump()), 400, "stature");
}

// The exports name their bones after SMPL or Unity's Humanoid, and say where the avatar came from.
TEST_F(ApiTest, ExportsTakeASkeletonNamingAndCarryProvenance) {
  json body = avatar_body(168, 62);
  body["skeleton"] = "humanoid";
  ApiResponse glb = call("POST", "/api/export/glb", body.dump());
  ASSERT_EQ(glb.status, 200) << glb.body;
  std::uint32_t length = 0;
  std::memcpy(&length, glb.body.data() + 12, 4);
  const json doc = json::parse(glb.body.substr(20, length));
  std::set<std::string> names;
  for (const auto& n : doc["nodes"]) names.insert(n.value("name", ""));
  EXPECT_TRUE(names.count("Hips") && names.count("LeftUpperArm") && names.count("Root")) << doc["nodes"].dump();
  EXPECT_FALSE(names.count("pelvis"));
  EXPECT_EQ(doc["asset"]["extras"]["caliper"]["body_model"], "toy-female");
  EXPECT_NEAR(doc["asset"]["extras"]["caliper"]["measurements"]["stature"]["value"].get<double>(), 168.0, 1e-9);
  ApiResponse vrm = call("POST", "/api/export/vrm", body.dump());
  ASSERT_EQ(vrm.status, 200) << vrm.body;
  EXPECT_EQ(vrm.download_name.substr(vrm.download_name.size() - 4), ".vrm");
  EXPECT_NE(vrm.body.find("VRMC_vrm"), std::string::npos);
  ApiResponse fbx = call("POST", "/api/export/fbx", body.dump());
  ASSERT_EQ(fbx.status, 200) << fbx.body;
  EXPECT_EQ(fbx.body.substr(0, 18), "Kaydara FBX Binary");
  EXPECT_EQ(fbx.download_name.substr(fbx.download_name.size() - 4), ".fbx");
  EXPECT_NE(fbx.body.find("toy-female"), std::string::npos);
  body["skeleton"] = "mixamo";
  const json e = expect_error(call("POST", "/api/export/glb", body.dump()), 400, "skeleton");
  EXPECT_NE(e["message"].get<std::string>().find("'smpl' or 'humanoid'"), std::string::npos) << e;
}

TEST_F(ApiTest, CsvMeasurementSetsAreReadWithUnitsHeadersAndComments) {
  const std::string csv =
      "measurement,value,unit\n"
      "# taped on 2024-05-02\n"
      "sex,male,\n"
      "height,1812,mm\n"
      "weight,81.5,kg\n"
      "arm_span,1.84,m\n"
      "inseam,84\n"
      "chest_circumference,101.5,cm\n";
  ApiResponse r = call("POST", "/api/measurement-set/import", csv, {}, "text/csv");
  ASSERT_EQ(r.status, 200) << r.body;
  json j = json::parse(r.body);
  EXPECT_EQ(j["sex"], "male");
  // Exactly the decimal a person would write (no 181.20000000000002 from unit conversion).
  EXPECT_EQ(j["measurements"]["stature"].get<double>(), 181.2);
  EXPECT_NE(r.body.find("\"stature\":181.2,"), std::string::npos) << r.body;
  EXPECT_NEAR(j["measurements"]["weight"].get<double>(), 81.5, 1e-9);
  EXPECT_NEAR(j["measurements"]["span"].get<double>(), 184.0, 1e-9);
  EXPECT_NEAR(j["measurements"]["crotch_height"].get<double>(), 84.0, 1e-9);
  EXPECT_NEAR(j["measurements"]["chest_circumference"].get<double>(), 101.5, 1e-9);
  EXPECT_EQ(j["measurements"].size(), 5u);
  // Semicolons (spreadsheets in many locales) work too.
  r = call("POST", "/api/measurement-set/import", "stature;165\nweight;60\n", {}, "text/csv");
  ASSERT_EQ(r.status, 200) << r.body;
}

TEST_F(ApiTest, BadMeasurementSetsAreRefusedNamingTheField) {
  expect_error(call("POST", "/api/measurement-set/import", "stature,abc,cm\n", {}, "text/csv"), 400, "stature");
  expect_error(call("POST", "/api/measurement-set/import", "stature,170,kg\n", {}, "text/csv"), 400, "stature");
  json e = expect_error(call("POST", "/api/measurement-set/import", "weight,3000\n", {}, "text/csv"), 400, "weight");
  EXPECT_EQ(e["accepted_range"]["max"], 300.0);
  expect_error(call("POST", "/api/measurement-set/import", "stature,170\nstature,171\n", {}, "text/csv"), 400, "stature");
  expect_error(call("POST", "/api/measurement-set/import", "wingspan,170\n", {}, "text/csv"), 400, "wingspan");
  expect_error(call("POST", "/api/measurement-set/import", "# nothing\n", {}, "text/csv"), 400, "body");
  expect_error(call("POST", "/api/measurement-set/import", R"({"measurements": {"stature": "x"}})"), 400, "stature");
  expect_error(call("POST", "/api/measurement-set/import", R"({"measurements": {"stature": 170)"), 400, "body");
  // The library's reader decides, as for `caliper avatar --measurements`: a newer version and a
  // JSON array are refused (the server's own reader once took both).
  expect_error(call("POST", "/api/measurement-set/import", R"({"version": 99, "measurements": {"stature": 170}})"), 400, "version");
  expect_error(call("POST", "/api/measurement-set/import", "[170, 60]"), 400, "body");
  expect_error(call("POST", "/api/measurement-set/export", avatar_body(170, 60).dump(), {{"format", "xml"}}), 400, "format");
}

TEST_F(ApiTest, MeasurementSetsRoundTripThroughCsvAndJson) {
  const json set = {{"sex", "female"},
                    {"measurements", {{"stature", 163.4}, {"weight", 58.25}, {"hip_breadth", 36.1}, {"waist_circumference", 71}}}};
  for (const char* format : {"csv", "json"}) {
    ApiResponse out = call("POST", "/api/measurement-set/export", set.dump(), {{"format", format}});
    ASSERT_EQ(out.status, 200) << out.body;
    EXPECT_FALSE(out.download_name.empty());
    ApiResponse back = call("POST", "/api/measurement-set/import", out.body, {},
                            std::string(format) == "csv" ? "text/csv" : "application/json");
    ASSERT_EQ(back.status, 200) << format << ": " << back.body;
    json j = json::parse(back.body);
    EXPECT_EQ(j["sex"], "female") << format;
    EXPECT_EQ(j["measurements"], set["measurements"]) << format;
  }
  // A Caliper report is a measurement set too: its requested values are read back.
  ApiResponse report = call("POST", "/api/export/report", avatar_body(171, 66).dump());
  ApiResponse back = call("POST", "/api/measurement-set/import", report.body);
  ASSERT_EQ(back.status, 200) << back.body;
  json j = json::parse(back.body);
  EXPECT_EQ(j["measurements"], json({{"stature", 171.0}, {"weight", 66.0}}));
  // And a flat object of values.
  back = call("POST", "/api/measurement-set/import", R"({"height": 170, "mass": 61})");
  ASSERT_EQ(back.status, 200) << back.body;
  EXPECT_EQ(json::parse(back.body)["measurements"], json({{"stature", 170.0}, {"weight", 61.0}}));
}

TEST_F(ApiTest, ConcurrentBuildsOnOneBuilderAgree) {
  const std::string body = avatar_body(166.0, 64.0, "R2").dump();
  const std::string expected = json::parse(call("POST", "/api/avatar", body).body)["mesh"]["positions"];
  std::vector<std::thread> threads;
  std::vector<int> ok(8, 0);
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&, t] {
      for (int i = 0; i < 10; ++i) {
        ApiResponse r = call("POST", "/api/avatar", body);
        if (r.status == 200 && json::parse(r.body)["mesh"]["positions"] == expected) ++ok[size_t(t)];
      }
    });
  for (auto& th : threads) th.join();
  for (int t = 0; t < 8; ++t) EXPECT_EQ(ok[size_t(t)], 10) << "thread " << t;
}

TEST(StaticFiles, ServesFilesInsideTheWebRoot) {
  const std::string root = test::toy_web_root();
  const std::string canonical_root = std::filesystem::canonical(root).string();
  EXPECT_EQ(resolve_static_path(root, "/"), canonical_root + "/index.html");
  EXPECT_EQ(resolve_static_path(root, "/app.js"), canonical_root + "/app.js");
  EXPECT_EQ(resolve_static_path(root, "/sub/file.txt"), canonical_root + "/sub/file.txt");
  EXPECT_EQ(resolve_static_path(root, "/missing.js"), std::nullopt);
  EXPECT_EQ(resolve_static_path(root, "/sub"), std::nullopt);  // a folder is not a file
}

TEST(StaticFiles, RefusesEveryWayOut) {
  const std::string root = test::toy_web_root();
  for (const char* path : {"/../secret.txt", "/sub/../../secret.txt", "/sub/../index.html", "/./index.html",
                           "/%2e%2e/secret.txt", "/%252e%252e/secret.txt", "/..%2fsecret.txt", "/..\\secret.txt",
                           "/sub\\..\\..\\secret.txt", "//etc/passwd", "/link.txt", "/.hidden", "relative.txt",
                           "/sub//file.txt", "/C:/windows", ""})
    EXPECT_EQ(resolve_static_path(root, path), std::nullopt) << path;
  EXPECT_EQ(resolve_static_path(root, std::string("/index.html\0.png", 16)), std::nullopt);
  EXPECT_EQ(resolve_static_path("", "/index.html"), std::nullopt);
  EXPECT_EQ(resolve_static_path(root + "/nonexistent", "/index.html"), std::nullopt);
}

TEST(StaticFiles, MimeTypes) {
  EXPECT_EQ(mime_type_for("a/index.html"), "text/html; charset=utf-8");
  EXPECT_EQ(mime_type_for("three.module.js"), "text/javascript; charset=utf-8");
  EXPECT_EQ(mime_type_for("style.css"), "text/css; charset=utf-8");
  EXPECT_EQ(mime_type_for("x.bin"), "application/octet-stream");
}

// Values that look mistyped are questioned with what was probably meant, unless the
// client says "force": true.
TEST_F(ApiTest, SuspectValuesAreQuestionedUnlessForced) {
  json e = expect_error(call("POST", "/api/avatar", avatar_body(60, 165).dump()), 400, "stature");
  EXPECT_EQ(e["kind"], "suspect_values");
  ASSERT_EQ(e["suspects"].size(), 2u);
  EXPECT_EQ(e["suggested_measurements"]["stature"], 165.0);
  EXPECT_EQ(e["suggested_measurements"]["weight"], 60.0);
  EXPECT_NE(e["message"].get<std::string>().find("swapped"), std::string::npos);
  e = expect_error(call("POST", "/api/avatar", avatar_body(1700, 60).dump()), 400, "stature");
  EXPECT_EQ(e["kind"], "suspect_values");
  EXPECT_EQ(e["suggested_measurements"]["stature"], 170.0);
  json body = avatar_body(60, 165);
  body["force"] = true;
  EXPECT_EQ(call("POST", "/api/avatar", body.dump()).status, 200);
  body["force"] = "yes";
  expect_error(call("POST", "/api/avatar", body.dump()), 400, "force");
  // The suggestion builds.
  EXPECT_EQ(call("POST", "/api/avatar", avatar_body(165, 60).dump()).status, 200);
}
}  // namespace
}  // namespace caliper::server
