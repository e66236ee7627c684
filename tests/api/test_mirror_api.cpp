// The virtual mirror's endpoints (docs/api.md "Mirror bodies", "Body-image tasks"): bodies with
// the weight changed for a measurement set or a session (same topology and rig, stature kept,
// weight growing, the list's limits), who may read them (as reading a session), and the
// body-image tasks stored with the session: started from the desktop only, read with the code,
// answered once (409 after), bad fields named, kept by a new server on the same database and
// carried by the session's JSON and tasks-CSV exports.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "api_calls.h"
#include "caliper/capture/measurement_set.h"
#include "caliper/capture/profiles.h"
#include "temp_files.h"
#include "test_capture_script.h"

namespace caliper::server {
namespace {

using nlohmann::json;
using test::TempDir;
using namespace test_calls;

// The toy body (api_fixture.h) measured: its stature kept, its width free to follow the weight.
const char* kToyMeasurements = R"({"sex": "female", "measurements": {"stature": 172}})";

// The bodies are one topology and rig; each is a whole body; stature stays, weight grows.
void expect_mirror_bodies(const json& j, const std::vector<double>& pcts) {
  const size_t joints = j["joint_names"].size();
  ASSERT_GT(joints, 0u);
  EXPECT_EQ(j["parents"].size(), joints);
  EXPECT_EQ(j["rest_pose"], "T");
  const size_t faces = j["faces"].size();
  ASSERT_EQ(faces % 3, 0u);
  const size_t vertices = j["skin"]["joints"].size();
  ASSERT_GT(vertices, 0u);
  EXPECT_EQ(j["skin"]["weights"].size(), vertices);
  for (const auto& f : j["faces"]) EXPECT_LT(f.get<size_t>(), vertices);
  for (size_t v = 0; v < vertices; ++v) {
    double sum = 0;
    for (int k = 0; k < 4; ++k) {
      EXPECT_LT(j["skin"]["joints"][v][k].get<size_t>(), joints);
      sum += j["skin"]["weights"][v][k].get<double>();
    }
    EXPECT_NEAR(sum, 1.0, 1e-6);
  }
  ASSERT_EQ(j["bodies"].size(), pcts.size());
  double previous = 0;
  for (size_t i = 0; i < pcts.size(); ++i) {
    const json& b = j["bodies"][i];
    SCOPED_TRACE(pcts[i]);
    EXPECT_EQ(b["weight_change_pct"].get<double>(), pcts[i]);
    EXPECT_EQ(b["vertices"].size(), vertices * 3);
    EXPECT_EQ(b["joints"].size(), joints * 3);
    // The body's own height: its highest vertex.
    double top = -1;
    for (size_t v = 0; v < vertices; ++v) top = std::max(top, b["vertices"][v * 3 + 1].get<double>());
    EXPECT_NEAR(top * 100, j["stature_cm"].get<double>(), 0.3);
    const double w = b["weight_kg"].get<double>();
    EXPECT_NEAR(w, j["weight_kg"].get<double>() * (1 + pcts[i] / 100), 0.03 * j["weight_kg"].get<double>());
    EXPECT_NEAR(b["bmi"].get<double>(), w / (top * top), 0.2);
    if (i > 0) {
      EXPECT_GT(w, previous);
    }
    previous = w;
    if (pcts[i] == 0) {
      EXPECT_NEAR(w, j["weight_kg"].get<double>(), 0.051);
    }
  }
}

TEST(MirrorApi, BodiesForAMeasurementSet) {
  TempDir dir;
  Api api(options_for(dir / "s.db"));
  const ApiResponse r = call(api, "POST", "/api/mirror-body", kToyMeasurements);
  ASSERT_EQ(r.status, 200) << r.body.substr(0, 400);
  expect_mirror_bodies(body_of(r), {-30, -20, -10, 0, 10, 20, 30});

  // The list: sorted, repeats dropped, 0 always there.
  json req = json::parse(kToyMeasurements);
  req["weights"] = {15, -5, 15};
  const ApiResponse some = call(api, "POST", "/api/mirror-body", req.dump());
  ASSERT_EQ(some.status, 200) << some.body.substr(0, 400);
  expect_mirror_bodies(body_of(some), {-5, 0, 15});
}

// A person at the edge of the model's population (a span the toy body can barely reach with
// that stature): the population holds no heavier or lighter body of hers, so the stature stays
// and the weight gives way, said in a warning instead of a body of another height.
TEST(MirrorApi, AtThePopulationsEdgeTheStatureStaysAndTheWeightGivesWay) {
  TempDir dir;
  Api api(options_for(dir / "s.db"));
  const ApiResponse r = call(api, "POST", "/api/mirror-body", R"({"measurements": {"stature": 172, "span": 175}, "weights": [-20, 20]})");
  ASSERT_EQ(r.status, 200) << r.body.substr(0, 400);
  const json j = body_of(r);
  ASSERT_EQ(j["bodies"].size(), 3u);
  for (const auto& b : j["bodies"]) EXPECT_NEAR(b["stature_cm"].get<double>(), j["stature_cm"].get<double>(), 0.3) << b["weight_change_pct"];
  bool said = false;
  for (const auto& w : j["warnings"]) said = said || w.get<std::string>().find("weight changed by 20.0 %: the body reaches") != std::string::npos;
  EXPECT_TRUE(said) << j["warnings"];
}

TEST(MirrorApi, BadWeightListsAreRefusedNamingTheField) {
  TempDir dir;
  Api api(options_for(dir / "s.db"));
  auto with = [](const json& weights) {
    json req = json::parse(kToyMeasurements);
    req["weights"] = weights;
    return req.dump();
  };
  json many = json::array();
  for (int i = 1; i <= 22; ++i) many.push_back(i);
  json twenty_one = json::array();
  for (int i = 1; i <= 21; ++i) twenty_one.push_back(i);  // 21 and the 0 added: 22
  for (const json& bad : {json(many), json(twenty_one), json::array({-60}), json::array({101}), json::array({"ten"}), json(10), json::array({nullptr})})
    expect_error(call(api, "POST", "/api/mirror-body", with(bad)), 400, "weights");
  const json range = body_of(call(api, "POST", "/api/mirror-body", with({150})));
  EXPECT_NE(range["error"]["message"].get<std::string>().find("[-50, 100]"), std::string::npos) << range.dump();
  expect_error(call(api, "POST", "/api/mirror-body", R"({"measurements": {"stature": 172}, "mesh": true})"), 400, "mesh");
  expect_error(call(api, "POST", "/api/mirror-body", R"({"measurements": {"stature": -1}})"), 400, "stature");
  expect_error(call(api, "GET", "/api/mirror-body"), 405, "method");
}

// A session measured by a scripted person through the capture endpoints, with weight and sex.
std::pair<std::string, std::string> measured_session(const Api& api) {
  const ApiResponse created = call(api, "POST", "/api/sessions", "{}", {}, kDesktop);
  EXPECT_EQ(created.status, 201) << created.body;
  const json c = body_of(created);
  const std::string id = c["session"]["id"], code = c["pairing_code"];
  test::ScriptedPerson person;
  test::SampleScript script(capture::ProfileRegistry::builtin().find("meta-quest-touch-plus")->tip_offset, 41);
  test::script_floor(script, person);
  test::script_core(script, person);
  for (const auto& batch : script.batches()) {
    json samples = json::array();
    for (const auto& s : batch)
      samples.push_back({{"t", s.t},
                         {"hand", s.hand == capture::Hand::Left ? "left" : "right"},
                         {"position", {s.position.x(), s.position.y(), s.position.z()}},
                         {"orientation", {s.orientation[0], s.orientation[1], s.orientation[2], s.orientation[3]}},
                         {"trigger", s.trigger}});
    const ApiResponse r = call(api, "POST", "/api/sessions/" + id + "/samples",
                               json{{"profile", "meta-quest-touch-plus"}, {"samples", samples}}.dump(), code);
    EXPECT_EQ(r.status, 200) << r.body;
  }
  const ApiResponse e = call(api, "POST", "/api/sessions/" + id + "/entries", R"({"weight_kg": 80, "sex": "female"})", code);
  EXPECT_EQ(e.status, 200) << e.body;
  return {id, code};
}

TEST(MirrorApi, SessionBodiesNeedWhatReadingTheSessionNeeds) {
  TempDir dir;
  Api api(options_for(dir / "s.db"));
  const auto [id, code] = measured_session(api);
  const std::string path = "/api/sessions/" + id + "/mirror-body";
  expect_error(call(api, "GET", path), 403, "pairing_code");
  expect_error(call(api, "GET", path, {}, "000000" == code ? "111111" : "000000"), 403, "pairing_code");
  const ApiResponse headset = call(api, "GET", path, {}, code, kHeadset, {{"weights", "-10,10"}});
  ASSERT_EQ(headset.status, 200) << headset.body.substr(0, 400);
  const json j = body_of(headset);
  EXPECT_EQ(j["sex"], "female");
  expect_mirror_bodies(j, {-10, 0, 10});
  const ApiResponse desktop = call(api, "GET", path, {}, {}, kDesktop);
  ASSERT_EQ(desktop.status, 200) << desktop.body.substr(0, 400);
  EXPECT_EQ(body_of(desktop)["bodies"].size(), 7u);

  for (const char* bad : {"ten", "-60", "10,,20", "1e999", "nan"})
    expect_error(call(api, "GET", path, {}, code, kHeadset, {{"weights", bad}}), 400, "weights");
  expect_error(call(api, "GET", path, {}, code, kHeadset, {{"sex", "male"}}), 400, "sex");
  expect_error(call(api, "POST", path, "{}", code), 405, "method");
  expect_error(call(api, "GET", "/api/sessions/s-000000000000/mirror-body", {}, {}, kDesktop), 404, "id");
  // A session that has measured nothing has no body yet.
  const json fresh = body_of(call(api, "POST", "/api/sessions", R"({"sex": "female"})", {}, kDesktop));
  expect_error(call(api, "GET", "/api/sessions/" + fresh["session"]["id"].get<std::string>() + "/mirror-body", {}, {}, kDesktop), 409,
               "session");
}

json start_task(const Api& api, const std::string& id, const json& task) {
  const ApiResponse r = call(api, "POST", "/api/sessions/" + id + "/body-image-tasks", task.dump(), {}, kDesktop);
  EXPECT_EQ(r.status, 201) << r.body;
  return body_of(r)["task"];
}

json answer_body(double chosen) {
  return {{"chosen_weight_change_pct", chosen}, {"shown_at_s", 12.0}, {"answered_at_s", 31.4}, {"adjustments", 14}};
}

TEST(MirrorApi, TasksStartAnswerAndAbandon) {
  TempDir dir;
  Api api(options_for(dir / "s.db"));
  const auto [id, code] = measured_session(api);
  const std::string tasks = "/api/sessions/" + id + "/body-image-tasks";

  // Starting is the experimenter's: the desktop only, even with the code.
  expect_error(call(api, "POST", tasks, R"({"kind": "adjust"})", code), 403, "session");
  const json first = start_task(api, id, {{"kind", "adjust"}, {"instruction", "how_i_look"}, {"start_weight_change_pct", 20},
                                          {"range_pct", {-30, 30}}});
  EXPECT_EQ(first["state"], "running");
  EXPECT_EQ(first["kind"], "adjust");
  EXPECT_EQ(first["start_weight_change_pct"], 20.0);
  EXPECT_EQ(first["range_pct"], json({-30.0, 30.0}));
  EXPECT_TRUE(first["answer"].is_null());
  EXPECT_EQ(first["id"].get<std::string>().rfind("t-", 0), 0u);

  // The headset reads them with the code.
  expect_error(call(api, "GET", tasks), 403, "pairing_code");
  json list = body_of(call(api, "GET", tasks, {}, code));
  ASSERT_EQ(list["tasks"].size(), 1u);
  EXPECT_EQ(list["current"]["id"], first["id"]);

  // Answered with the code; the answer carries the weight the change means for her (80 kg
  // entered, stature measured by the scripted person).
  const std::string answer = tasks + "/" + first["id"].get<std::string>() + "/answer";
  expect_error(call(api, "POST", answer, answer_body(7.5).dump()), 403, "pairing_code");
  const ApiResponse ok = call(api, "POST", answer, answer_body(7.5).dump(), code);
  ASSERT_EQ(ok.status, 200) << ok.body;
  const json done = body_of(ok)["task"];
  EXPECT_EQ(done["state"], "answered");
  const json& a = done["answer"];
  EXPECT_EQ(a["chosen_weight_change_pct"], 7.5);
  EXPECT_NEAR(a["chosen_weight_kg"].get<double>(), 86.0, 0.01);
  const double stature = test::ScriptedPerson().stature();
  EXPECT_NEAR(a["chosen_bmi"].get<double>(), 86.0 / (stature * stature), 0.05);
  EXPECT_EQ(a["shown_at_s"], 12.0);
  EXPECT_EQ(a["answered_at_s"], 31.4);
  EXPECT_EQ(a["adjustments"], 14);
  EXPECT_EQ(a["answered"].get<std::string>().size(), 20u);  // 2026-11-25T16:00:00Z
  list = body_of(call(api, "GET", tasks, {}, code));
  EXPECT_TRUE(list["current"].is_null());

  // Only a running task takes an answer.
  expect_error(call(api, "POST", answer, answer_body(5).dump(), code), 409, "task_id");

  // A new task abandons the running one.
  const json second = start_task(api, id, {{"kind", "adjust"}, {"instruction", "how_i_would_like_to_look"}});
  const json third = start_task(api, id, {{"kind", "show"}, {"instruction", "Look at yourself, please"}, {"start_weight_change_pct", -10}});
  list = body_of(call(api, "GET", tasks, {}, {}, kDesktop));
  ASSERT_EQ(list["tasks"].size(), 3u);
  EXPECT_EQ(list["tasks"][1]["state"], "abandoned");
  EXPECT_EQ(list["tasks"][2]["state"], "running");
  EXPECT_EQ(list["current"]["id"], third["id"]);
  expect_error(call(api, "POST", tasks + "/" + second["id"].get<std::string>() + "/answer", answer_body(0).dump(), code), 409,
               "task_id");
  // A show task takes no answer.
  expect_error(call(api, "POST", tasks + "/" + third["id"].get<std::string>() + "/answer", answer_body(0).dump(), code), 409,
               "task_id");
  expect_error(call(api, "POST", tasks + "/t-000000000000/answer", answer_body(0).dump(), code), 404, "task_id");
  expect_error(call(api, "GET", tasks + "/" + third["id"].get<std::string>() + "/answer", {}, code), 405, "method");
  expect_error(call(api, "GET", "/api/sessions/s-000000000000/body-image-tasks", {}, {}, kDesktop), 404, "id");

  // A new server on the same database has them all, and the exports carry them.
  Api again(options_for(dir / "s.db"));
  list = body_of(call(again, "GET", tasks, {}, code));
  ASSERT_EQ(list["tasks"].size(), 3u);
  EXPECT_EQ(list["tasks"][0]["answer"], a);
  const ApiResponse exported = call(again, "GET", "/api/sessions/" + id + "/export", {}, code, kHeadset, {{"format", "json"}});
  ASSERT_EQ(exported.status, 200) << exported.body;
  const json e = body_of(exported);
  ASSERT_EQ(e["body_image_tasks"].size(), 3u);
  EXPECT_EQ(e["body_image_tasks"][0], list["tasks"][0]);
  EXPECT_EQ(parse_measurement_set(exported.body).edge.at("weight"), 80.0);  // still a measurement set
  const ApiResponse csv = call(again, "GET", "/api/sessions/" + id + "/export", {}, code, kHeadset, {{"format", "tasks-csv"}});
  ASSERT_EQ(csv.status, 200) << csv.body;
  EXPECT_EQ(csv.download_name, "caliper-" + id + "-tasks.csv");
  EXPECT_EQ(csv.body.rfind("task_id,kind,instruction,start_weight_change_pct,range_min_pct,range_max_pct,state,created,"
                           "chosen_weight_change_pct,chosen_weight_kg,chosen_bmi,shown_at_s,answered_at_s,adjustments,answered\n",
                           0),
            0u);
  EXPECT_NE(csv.body.find(first["id"].get<std::string>() + ",adjust,how_i_look,20,-30,30,answered,"), std::string::npos) << csv.body;
  EXPECT_NE(csv.body.find(",7.5,86,"), std::string::npos) << csv.body;
  EXPECT_NE(csv.body.find(",show,\"Look at yourself, please\",-10,-30,30,running,"), std::string::npos) << csv.body;
  EXPECT_EQ(std::count(csv.body.begin(), csv.body.end(), '\n'), 4);
}

TEST(MirrorApi, BadTasksAndAnswersNameTheField) {
  TempDir dir;
  Api api(options_for(dir / "s.db"));
  const auto [id, code] = measured_session(api);
  const std::string tasks = "/api/sessions/" + id + "/body-image-tasks";
  auto start = [&](const std::string& body) { return call(api, "POST", tasks, body, {}, kDesktop); };
  expect_error(start(R"({"kind": "stare"})"), 400, "kind");
  expect_error(start(R"({"kind": 3})"), 400, "kind");
  expect_error(start(R"({"instruction": ""})"), 400, "instruction");
  expect_error(start(json{{"instruction", std::string(201, 'a')}}.dump()), 400, "instruction");
  expect_error(start(json{{"instruction", "two\nlines"}}.dump()), 400, "instruction");
  EXPECT_EQ(start(json{{"instruction", std::string(100, 'a') + std::string(100, 'e') /* 200 */}}.dump()).status, 201);
  EXPECT_EQ(start(json{{"instruction", "Wie sehe ich aus? " + std::string(60, 'a') + "\u00e4\u00f6\u00fc"}}.dump()).status, 201);
  expect_error(start(R"({"range_pct": [30, -30]})"), 400, "range_pct");
  expect_error(start(R"({"range_pct": [-30]})"), 400, "range_pct");
  expect_error(start(R"({"range_pct": [-60, 30]})"), 400, "range_pct");
  expect_error(start(R"({"range_pct": [-30, null]})"), 400, "range_pct");
  expect_error(start(R"({"start_weight_change_pct": 40})"), 400, "start_weight_change_pct");
  expect_error(start(R"({"start_weight_change_pct": "10"})"), 400, "start_weight_change_pct");
  expect_error(start(R"({"colour": "red"})"), 400, "colour");
  expect_error(start("not json"), 400, "body");

  const json t = start_task(api, id, {{"kind", "adjust"}, {"range_pct", {-20, 40}}});
  const std::string answer = tasks + "/" + t["id"].get<std::string>() + "/answer";
  const std::string pairing = code;  // a lambda may not capture a structured binding (clang 14)
  auto send = [&](const json& body) { return call(api, "POST", answer, body.dump(), pairing); };
  json bad = answer_body(45);
  expect_error(send(bad), 400, "chosen_weight_change_pct");
  bad = answer_body(-21);
  expect_error(send(bad), 400, "chosen_weight_change_pct");
  bad = answer_body(5);
  bad["chosen_weight_change_pct"] = nullptr;
  expect_error(send(bad), 400, "chosen_weight_change_pct");
  bad = answer_body(5);
  bad["answered_at_s"] = 3.0;  // before it was shown
  expect_error(send(bad), 400, "answered_at_s");
  bad = answer_body(5);
  bad["shown_at_s"] = -1.0;
  expect_error(send(bad), 400, "shown_at_s");
  bad = answer_body(5);
  bad["adjustments"] = 2.5;
  expect_error(send(bad), 400, "adjustments");
  bad = answer_body(5);
  bad["adjustments"] = -1;
  expect_error(send(bad), 400, "adjustments");
  bad = answer_body(5);
  bad.erase("shown_at_s");
  expect_error(send(bad), 400, "shown_at_s");
  bad = answer_body(5);
  bad["mood"] = "fine";
  expect_error(send(bad), 400, "mood");
  // None of those changed the task: the good answer still goes through, once.
  EXPECT_EQ(send(answer_body(40)).status, 200);
  expect_error(send(answer_body(40)), 409, "task_id");
}

}  // namespace
}  // namespace caliper::server
