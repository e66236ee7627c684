// Whose input failed, through Api::handle: the client's input is a 4xx naming the
// field; the server's own broken file (a model in its models folder, the maps inside one, its
// controller profiles) is a 500 whose body names no file-system path.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "api.h"
#include "api_fixture.h"
#include "caliper/caliper.h"
#include "temp_files.h"

namespace caliper::server {
namespace {

using nlohmann::json;
using test::TempDir;

ApiResponse call(const Api& api, const std::string& method, const std::string& path, const std::string& body = {},
                 std::map<std::string, std::string> query = {}) {
  ApiRequest req;
  req.method = method;
  req.path = path;
  req.body = body;
  req.query = std::move(query);
  req.content_type = "application/json";
  req.remote_address = "127.0.0.1";
  return api.handle(req);
}

// A models folder holding the toy body (good) and the broken files each test adds.
struct ModelsFolder {
  TempDir dir;
  ApiOptions options;
  ModelsFolder() {
    std::filesystem::create_directories(dir / "models");
    std::filesystem::copy_file(test::toy_models_dir() + "/toy-female.npz", dir / "models/toy-female.npz");
    options.models_dir = dir / "models";
    options.default_model = "toy";
    options.sessions_database = dir / "sessions.db";
  }
  std::string models() const { return dir / "models"; }
};

const std::string kAvatar = R"({"sex": "female", "model": "%s", "measurements": {"stature": 170, "weight": 60}})";
std::string avatar_body(const std::string& model) {
  std::string body = kAvatar;
  return body.replace(body.find("%s"), 2, model);
}

// A 500 of the given kind, no field, and no path of the server's files in the body.
void expect_installation_error(const ApiResponse& r, const std::string& kind, const std::string& folder) {
  EXPECT_EQ(r.status, 500) << r.body;
  const json e = json::parse(r.body)["error"];
  EXPECT_EQ(e["kind"], kind) << r.body;
  EXPECT_TRUE(e["field"].is_null()) << r.body;
  EXPECT_EQ(r.body.find(folder), std::string::npos) << r.body;
  EXPECT_EQ(r.body.find(".npz"), std::string::npos) << r.body;
  EXPECT_EQ(r.body.find(".json"), std::string::npos) << r.body;
  EXPECT_NE(e["message"].get<std::string>().find("not at fault"), std::string::npos) << r.body;
}

TEST(ErrorOrigin, ABrokenModelInTheModelsFolderIsA500WithoutPaths) {
  ModelsFolder f;
  test::write_file(f.models() + "/broken-female.npz", "this is not a zip");
  const Api api(f.options);
  expect_installation_error(call(api, "POST", "/api/avatar", avatar_body("broken")), "model_format", f.models());
  expect_installation_error(call(api, "POST", "/api/export/glb", avatar_body("broken")), "model_format", f.models());
  expect_installation_error(call(api, "GET", "/api/topology", {}, {{"model", "broken"}, {"sex", "female"}}),
                            "model_format", f.models());
  // The good model beside it still works, and the client's own mistakes stay 4xx naming the field.
  EXPECT_EQ(call(api, "POST", "/api/avatar", avatar_body("toy")).status, 200);
  const ApiResponse unknown = call(api, "POST", "/api/avatar", avatar_body("nobody"));
  EXPECT_EQ(unknown.status, 400) << unknown.body;
  EXPECT_EQ(json::parse(unknown.body)["error"]["field"], "model");
}

TEST(ErrorOrigin, BrokenMapsInsideAnInstalledModelAreA500) {
  ModelsFolder f;
  BodyModelData d = load_native_model(f.models() + "/toy-female.npz").data();
  d.name = "badmaps-female";
  d.metadata["real_to_virtual"] = R"({"format": "caliper-real-to-virtual", "maps": {"stature": {"slope": 1, "pairs": "20"}}})";
  save_model(BodyModel(std::move(d)), f.models() + "/badmaps-female.npz");
  const Api api(f.options);
  expect_installation_error(call(api, "POST", "/api/avatar", avatar_body("badmaps")), "model_format", f.models());
}

TEST(ErrorOrigin, AnUploadedMeasurementSetIsTheClients) {
  ModelsFolder f;
  const Api api(f.options);
  for (const auto& [body, field] : std::vector<std::pair<std::string, std::string>>{
           {R"({"measurements": {"stature": "tall"}})", "stature"},
           {R"({"version": 99, "measurements": {"stature": 170}})", "version"},
           {"stature,170,furlongs\n", "stature"},
           {"[1, 2]", "body"},
           {R"({"measurements": {"stature": 1700}})", "stature"}}) {
    const ApiResponse r = call(api, "POST", "/api/measurement-set/import", body);
    EXPECT_EQ(r.status, 400) << body << " → " << r.body;
    EXPECT_EQ(json::parse(r.body)["error"]["field"], field) << body;
  }
}

TEST(ErrorOrigin, ABrokenProfilesFileOrDatabaseNamesNoPath) {
  ModelsFolder f;
  test::write_file(f.dir / "profiles.json", R"({"profiles": {"pen": {"tip_offset_m": [0, 0, 9]}}})");
  ApiOptions o = f.options;
  o.capture_profiles_file = f.dir / "profiles.json";
  const Api broken_profiles(o);
  expect_installation_error(call(broken_profiles, "GET", "/api/capture/profiles"), "database_format",
                            f.dir.path.string());
  // A foreign file where the sessions database should be: unavailable, path kept for the log only.
  test::write_file(f.dir / "foreign.db", "not a database, somebody else's file\n");
  o = f.options;
  o.sessions_database = f.dir / "foreign.db";
  const Api foreign(o);
  const ApiResponse r = call(foreign, "GET", "/api/sessions");
  EXPECT_EQ(r.status, 503) << r.body;
  EXPECT_EQ(r.body.find(f.dir.path.string()), std::string::npos) << r.body;
}

}  // namespace
}  // namespace caliper::server
