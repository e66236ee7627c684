// The capture endpoints (docs/api.md "Capture sessions"): a scripted person measured through
// the JSON API (values checked against the person's landmarks), pairing (403 without or with a
// wrong code, 429 after repeated wrong codes from one address, 423 once a session's budget of
// wrong codes is spent, whatever the addresses; a new code from the desktop only), who may read
// what (the desktop lists and reads everything; other devices see stubs and need the code), bad input (null/NaN, malformed JSON, huge batches,
// unknown fields → 4xx naming the field), a server dropped mid-session and a new one resuming,
// and the same over real HTTP and HTTPS (headers reach the API; the self-signed certificate works).
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "api_calls.h"
#include "capture_api.h"
#include "caliper/capture/measurement_set.h"
#include "caliper/errors.h"
#include "caliper/capture/profiles.h"
#include "temp_files.h"
#include "test_capture_script.h"
// httplib after Eigen (its <resolv.h> defines `_res`).
#include <httplib.h>

#include "server.h"
#include "tls_certificate.h"

namespace caliper::server {
namespace {

using nlohmann::json;
using test::SampleScript;
using test::ScriptedPerson;
using test::TempDir;
using namespace test_calls;

const Eigen::Vector3d kTouchPlus = capture::ProfileRegistry::builtin().find("meta-quest-touch-plus")->tip_offset;

json samples_json(const std::vector<capture::ControllerSample>& batch) {
  json arr = json::array();
  for (const auto& s : batch)
    arr.push_back({{"t", s.t},
                   {"hand", s.hand == capture::Hand::Left ? "left" : "right"},
                   {"position", {s.position.x(), s.position.y(), s.position.z()}},
                   {"orientation", {s.orientation[0], s.orientation[1], s.orientation[2], s.orientation[3]}},
                   {"trigger", s.trigger}});
  return arr;
}

// Sends the script's samples in ~100 ms batches; returns every event.
json send(const Api& api, const std::string& id, const std::string& code, SampleScript& s) {
  json events = json::array();
  for (const auto& b : s.batches()) {
    const ApiResponse r = call(api, "POST", "/api/sessions/" + id + "/samples",
                               json{{"profile", "meta-quest-touch-plus"}, {"samples", samples_json(b)}}.dump(), code);
    EXPECT_EQ(r.status, 200) << r.body;
    const json j = body_of(r);  // kept: a range-for over a temporary's member would dangle
    for (const auto& e : j["events"]) events.push_back(e);
  }
  return events;
}

std::pair<std::string, std::string> create(const Api& api, const json& body = json::object()) {
  const ApiResponse r = call(api, "POST", "/api/sessions", body.dump());
  EXPECT_EQ(r.status, 201) << r.body;
  const json j = body_of(r);
  return {j["session"]["id"].get<std::string>(), j["pairing_code"].get<std::string>()};
}

TEST(CaptureApi, ProfilesListTipOffsets) {
  TempDir dir;
  Api api(options_for(dir / "s.db"));
  const ApiResponse r = call(api, "GET", "/api/capture/profiles");
  ASSERT_EQ(r.status, 200);
  const json j = body_of(r);
  EXPECT_TRUE(j["profiles"].contains(j["default"].get<std::string>()));
  for (const char* id : {"oculus-touch-v3", "meta-quest-touch-plus", "htc-vive"}) {
    ASSERT_TRUE(j["profiles"].contains(id)) << id;
    EXPECT_EQ(j["profiles"][id]["tip_offset_m"].size(), 3u);
  }
  EXPECT_DOUBLE_EQ(j["profiles"]["meta-quest-touch-plus"]["tip_offset_m"][2].get<double>(), kTouchPlus.z());
}

// The capture page's QR code: the address a headset opens. Listening on one address, it is the
// Host the page used (a loopback name is flagged as this machine only); on all interfaces, each
// LAN address, with the scheme and the port the page used.
TEST(CaptureApi, HeadsetAddressFollowsHowTheServerIsReached) {
  TempDir dir;
  auto headset = [](const Api& api, const std::string& host) {
    ApiRequest r;
    r.method = "GET";
    r.path = "/api/capture/headset";
    r.remote_address = "127.0.0.1";
    r.local_address = "127.0.0.1";
    if (!host.empty()) r.headers["host"] = host;
    return api.handle(r);
  };
  Api plain(options_for(dir / "s.db"));
  json j = body_of(headset(plain, "127.0.0.1:8123"));
  EXPECT_EQ(j["urls"], json({"http://127.0.0.1:8123/capture.html"}));
  EXPECT_FALSE(j["other_devices"].get<bool>());
  j = body_of(headset(plain, "192.168.1.5:8080"));
  EXPECT_EQ(j["urls"], json({"http://192.168.1.5:8080/capture.html"}));
  EXPECT_TRUE(j["other_devices"].get<bool>());
  EXPECT_EQ(body_of(headset(plain, "[::1]:9000"))["urls"], json({"http://[::1]:9000/capture.html"}));
  EXPECT_FALSE(body_of(headset(plain, "localhost"))["other_devices"].get<bool>());
  ApiOptions lan = options_for(dir / "s.db");
  lan.https = true;
  lan.headset_hosts = {"192.168.1.5", "10.0.0.7"};
  j = body_of(headset(Api(lan), "127.0.0.1:8080"));
  EXPECT_EQ(j["urls"], json({"https://192.168.1.5:8080/capture.html", "https://10.0.0.7:8080/capture.html"}));
  EXPECT_TRUE(j["other_devices"].get<bool>());
  EXPECT_EQ(call(plain, "POST", "/api/capture/headset", "{}").status, 405);
}

TEST(CaptureApi, AScriptedPersonMeasuredThroughTheApi) {
  TempDir dir;
  Api api(options_for(dir / "s.db"));
  const auto [id, code] = create(api, {{"mode", "self"}, {"steps", "core"}});
  ASSERT_EQ(code.size(), 6u);
  json s = body_of(call(api, "GET", "/api/sessions/" + id, {}, code))["session"];
  EXPECT_EQ(s["state"], "floor");
  EXPECT_EQ(s["step"]["name"], "floor");
  EXPECT_EQ(s["step"]["kind"], "floor");
  EXPECT_EQ(s["step"]["points_needed"], 5);
  EXPECT_EQ(s["progress"]["total"], 6);
  EXPECT_TRUE(s["floor_m"].is_null());
  EXPECT_FALSE(s.contains("pairing_code"));

  ScriptedPerson person;
  SampleScript script(kTouchPlus, 31);
  script.hold(1, Eigen::Vector3d(0, person.floor, 0.3), 0.4);  // a short press first
  test::script_floor(script, person);
  test::script_core(script, person);
  const json events = send(api, id, code, script);
  int accepted = 0, rejected = 0, steps = 0, done = 0;
  for (const auto& e : events) {
    if (e["type"] == "point_accepted") ++accepted;
    if (e["type"] == "point_rejected") {
      ++rejected;
      EXPECT_NE(e["reason"].get<std::string>().find("held 0.4 s"), std::string::npos) << e.dump();
    }
    if (e["type"] == "step_done") ++steps;
    if (e["type"] == "session_done") ++done;
  }
  EXPECT_EQ(accepted, 15);
  EXPECT_EQ(rejected, 1);
  EXPECT_EQ(steps, 6);
  EXPECT_EQ(done, 1);

  s = body_of(call(api, "GET", "/api/sessions/" + id, {}, code))["session"];
  EXPECT_EQ(s["state"], "entries");
  EXPECT_TRUE(s["step"].is_null());
  EXPECT_EQ(s["values"]["stature"]["repetitions_cm"].size(), 2u);
  EXPECT_EQ(s["points"].size(), 15u);
  const ApiResponse entries = call(api, "POST", "/api/sessions/" + id + "/entries", R"({"weight_kg": 70.5, "sex": "male"})", code);
  ASSERT_EQ(entries.status, 200) << entries.body;
  s = body_of(entries)["session"];
  EXPECT_EQ(s["state"], "done");
  EXPECT_EQ(s["measurement_set"]["weight"], 70.5);

  for (const std::string format : {"json", "csv"}) {
    const ApiResponse e = call(api, "GET", "/api/sessions/" + id + "/export", {}, code, kHeadset, {{"format", format}});
    ASSERT_EQ(e.status, 200) << e.body;
    EXPECT_FALSE(e.download_name.empty());
    const MeasurementSetFile set = parse_measurement_set(e.body);
    ASSERT_TRUE(set.sex);
    EXPECT_EQ(*set.sex, Sex::Male);
    EXPECT_NEAR(set.edge.at("stature"), person.stature() * 100, 0.25);
    EXPECT_NEAR(set.edge.at("span"), person.span() * 100, 0.1);
    EXPECT_NEAR(set.edge.at("crotch_height"), person.crotch_height() * 100, 0.25);
    EXPECT_NEAR(set.edge.at("hip_breadth"), person.hip_breadth() * 100, 0.1);
    EXPECT_NEAR(set.edge.at("arm_length"), person.arm_length() * 100, 0.1);
    EXPECT_DOUBLE_EQ(set.edge.at("weight"), 70.5);
  }
  // The desktop tool's own importer accepts the export.
  const ApiResponse exported = call(api, "GET", "/api/sessions/" + id + "/export", {}, {}, kDesktop);  // the desktop
  const ApiResponse imported = call(api, "POST", "/api/measurement-set/import", exported.body);
  EXPECT_EQ(imported.status, 200) << imported.body;

  const json list = body_of(call(api, "GET", "/api/sessions", {}, {}, kDesktop));
  ASSERT_EQ(list["sessions"].size(), 1u);
  EXPECT_FALSE(list["sessions"][0].contains("points"));
  EXPECT_EQ(list["sessions"][0]["id"], id);
  EXPECT_EQ(list["sessions"][0]["measurement_set"]["weight"], 70.5);
}

TEST(CaptureApi, UndoAndRedo) {
  TempDir dir;
  Api api(options_for(dir / "s.db"));
  const auto [id, code] = create(api);
  ScriptedPerson person;
  SampleScript script(kTouchPlus, 32);
  test::script_floor(script, person);
  send(api, id, code, script);
  json s = body_of(call(api, "POST", "/api/sessions/" + id + "/undo", "", code))["session"];
  EXPECT_EQ(s["state"], "floor");
  EXPECT_EQ(s["step"]["points_done"], 4);
  EXPECT_EQ(s["can_redo"], true);
  s = body_of(call(api, "POST", "/api/sessions/" + id + "/redo", "", code))["session"];
  EXPECT_EQ(s["state"], "measuring");
  EXPECT_EQ(s["step"]["name"], "stature");
  EXPECT_EQ(s["can_redo"], false);
  expect_error(call(api, "POST", "/api/sessions/" + id + "/undo"), 403, "pairing_code");
}

TEST(CaptureApi, WritesNeedThePairingCode) {
  TempDir dir;
  Api api(options_for(dir / "s.db"));
  const auto [id, code] = create(api);
  const std::string batch = json{{"samples", json::array()}}.dump();
  expect_error(call(api, "POST", "/api/sessions/" + id + "/samples", batch), 403, "pairing_code");
  std::string wrong = code;
  wrong[5] = wrong[5] == '0' ? '1' : '0';
  expect_error(call(api, "POST", "/api/sessions/" + id + "/samples", batch, wrong), 403, "pairing_code");
  expect_error(call(api, "POST", "/api/sessions/" + id + "/entries", R"({"weight_kg": 60})", wrong), 403, "pairing_code");
  expect_error(call(api, "DELETE", "/api/sessions/" + id), 403, "pairing_code");
  EXPECT_EQ(call(api, "POST", "/api/sessions/" + id + "/samples", batch, code).status, 200);
  // The same wrong code again is refused but is no new guess: it does not count.
  for (int i = 0; i < 6; ++i) expect_error(call(api, "POST", "/api/sessions/" + id + "/undo", "", wrong), 403, "pairing_code");
  // Guessing is slowed down per device: after 5 wrong codes in a minute even the right one waits.
  for (int i = 0; i < 4; ++i) {
    std::string guess = wrong;
    guess[0] = static_cast<char>('0' + (code[0] - '0' + 1 + i) % 10);
    expect_error(call(api, "POST", "/api/sessions/" + id + "/undo", "", guess), 403, "pairing_code");
  }
  const ApiResponse waiting = call(api, "POST", "/api/sessions/" + id + "/undo", "", code);
  expect_error(waiting, 429, "pairing_code");
  EXPECT_EQ(body_of(waiting)["error"]["kind"], "too_many_attempts");
  // ... from that device only: the headset, elsewhere on the network, goes on with the right code.
  EXPECT_EQ(call(api, "POST", "/api/sessions/" + id + "/undo", "", code, "192.168.1.31").status, 200);
  // Another session is not affected.
  const auto [id2, code2] = create(api);
  EXPECT_EQ(call(api, "DELETE", "/api/sessions/" + id2, "", code2).status, 204);
  expect_error(call(api, "GET", "/api/sessions/" + id2, {}, {}, kDesktop), 404, "id");
}

// The audit's attack: a new client address for every guess. The per-address throttle never
// triggers, but the session's own budget does: 10 wrong codes in all, then 423 for every code,
// the right one too, until the experimenter's desktop issues a new code.
TEST(CaptureApi, RotatingAddressesCannotGuessMoreThanTheSessionsBudget) {
  TempDir dir;
  Api api(options_for(dir / "s.db"));
  const auto [id, code] = create(api);
  int tried = 0, locked = 0;
  for (int i = 0; i < 40; ++i) {
    std::string guess = code;
    guess[0] = static_cast<char>('0' + (code[0] - '0' + 1 + i % 9) % 10);  // never the code
    guess[1] = static_cast<char>('0' + i / 9);
    const std::string address = "10.0." + std::to_string(i / 200) + "." + std::to_string(i % 200 + 1);
    const ApiResponse r = call(api, "POST", "/api/sessions/" + id + "/undo", "", guess, address);
    EXPECT_NE(r.status, 429) << "each address guesses once: the per-address throttle never sees it";
    if (r.status == 403) ++tried;
    if (r.status == 423) {
      ++locked;
      EXPECT_EQ(body_of(r)["error"]["kind"], "pairing_locked") << r.body;
      EXPECT_EQ(body_of(r)["error"]["field"], "pairing_code") << r.body;
      EXPECT_NE(body_of(r)["error"]["message"].get<std::string>().find("new code"), std::string::npos) << r.body;
    }
  }
  EXPECT_EQ(tried, 9);    // the 10th wrong code already answers 423
  EXPECT_EQ(locked, 31);
  // The right code, from a fresh address or the headset's: refused, for writes and reads alike.
  expect_error(call(api, "POST", "/api/sessions/" + id + "/samples", json{{"samples", json::array()}}.dump(), code, "10.9.9.9"),
               423, "pairing_code");
  expect_error(call(api, "GET", "/api/sessions/" + id, {}, code, "192.168.1.30"), 423, "pairing_code");
  // A new server (restart) keeps the lock.
  Api restarted(options_for(dir / "s.db"));
  expect_error(call(restarted, "POST", "/api/sessions/" + id + "/undo", "", code, "192.168.1.30"), 423, "pairing_code");
  // Only the desktop may issue a new code; it unlocks the session.
  expect_error(call(restarted, "POST", "/api/sessions/" + id + "/pairing", "", code, "192.168.1.30"), 403, "pairing_code");
  const ApiResponse reissued = call(restarted, "POST", "/api/sessions/" + id + "/pairing", "", {}, kDesktop);
  ASSERT_EQ(reissued.status, 200) << reissued.body;
  const std::string fresh = body_of(reissued)["pairing_code"];
  ASSERT_EQ(fresh.size(), 6u);
  EXPECT_EQ(body_of(reissued)["session"]["id"], id);
  EXPECT_EQ(call(restarted, "POST", "/api/sessions/" + id + "/undo", "", fresh, "192.168.1.30").status, 200);
  if (fresh != code) expect_error(call(restarted, "POST", "/api/sessions/" + id + "/undo", "", code, "192.168.1.31"), 403, "pairing_code");
  expect_error(call(restarted, "POST", "/api/sessions/s-nope/pairing", "", {}, kDesktop), 404, "id");
}

// Who may read what: the desktop (loopback, or a browser on the server's own LAN address) lists
// every session with its values and reads any session; another device gets stubs in the list and
// must show the session's code to read it or export it.
TEST(CaptureApi, OnlyTheDesktopListsMeasurementsOthersNeedTheCode) {
  TempDir dir;
  Api api(options_for(dir / "s.db"));
  const auto [id, code] = create(api, {{"sex", "female"}, {"weight_kg", 61.5}});
  const json stubs = body_of(call(api, "GET", "/api/sessions"));  // from a headset
  ASSERT_EQ(stubs["sessions"].size(), 1u);
  const json stub = stubs["sessions"][0];
  EXPECT_EQ(stub["id"], id);
  EXPECT_EQ(stub["state"], "floor");
  for (const char* hidden : {"values", "measurement_set", "weight_kg", "sex", "points", "step"})
    EXPECT_FALSE(stub.contains(hidden)) << hidden << " in " << stub.dump();
  for (const char* desktop : {"127.0.0.1", "::1", "::ffff:127.0.0.1"}) {
    const json full = body_of(call(api, "GET", "/api/sessions", {}, {}, desktop));
    EXPECT_EQ(full["sessions"][0]["measurement_set"]["weight"], 61.5) << desktop;
    EXPECT_EQ(call(api, "GET", "/api/sessions/" + id, {}, {}, desktop).status, 200) << desktop;
  }
  // The browser on the server's machine using its LAN address (e.g. https://192.168.1.23:8080).
  ApiRequest same_machine;
  same_machine.method = "GET";
  same_machine.path = "/api/sessions";
  same_machine.remote_address = same_machine.local_address = "192.168.1.23";
  EXPECT_EQ(body_of(api.handle(same_machine))["sessions"][0]["sex"], "female");
  for (const std::string& path : std::vector<std::string>{"/api/sessions/" + id, "/api/sessions/" + id + "/export"}) {
    expect_error(call(api, "GET", path), 403, "pairing_code");
    std::string wrong = code;
    wrong[2] = wrong[2] == '0' ? '1' : '0';
    expect_error(call(api, "GET", path, {}, wrong), 403, "pairing_code");
    EXPECT_EQ(call(api, "GET", path, {}, code).status, 200) << path;
  }
  const ApiResponse exported = call(api, "GET", "/api/sessions/" + id + "/export", {}, code, kHeadset, {{"format", "csv"}});
  EXPECT_NE(exported.body.find("61.5"), std::string::npos) << exported.body;
  expect_error(call(api, "GET", "/api/sessions/s-nope", {}, code), 404, "id");
}

TEST(CaptureApi, BadInputIsA4xxNamingTheField) {
  TempDir dir;
  Api api(options_for(dir / "s.db"));
  const auto [id, code] = create(api);
  const std::string path = "/api/sessions/" + id + "/samples";
  auto sample = [] {
    return json{{"t", 1.0}, {"hand", "left"}, {"position", {0, 1, 0}}, {"orientation", {0, 0, 0, 1}}, {"trigger", 0}};
  };
  json bad = sample();
  bad["position"][1] = nullptr;  // JSON.stringify(NaN)
  expect_error(call(api, "POST", path, json{{"samples", {sample(), bad}}}.dump(), code), 400, "samples[1].position");
  expect_error(call(api, "POST", path, R"({"samples": [{"t": 1, "hand": "left", "position": [0, NaN, 0]}]})", code), 400, "body");
  expect_error(call(api, "POST", path, "{\"samples\": [", code), 400, "body");
  expect_error(call(api, "POST", path, "", code), 400, "body");
  bad = sample();
  bad["trigger"] = 2;
  expect_error(call(api, "POST", path, json{{"samples", {bad}}}.dump(), code), 400, "samples[0].trigger");
  bad = sample();
  bad["hand"] = "middle";
  expect_error(call(api, "POST", path, json{{"samples", {bad}}}.dump(), code), 400, "samples[0].hand");
  bad = sample();
  bad["orientation"] = {0, 0, 0};
  expect_error(call(api, "POST", path, json{{"samples", {bad}}}.dump(), code), 400, "samples[0].orientation");
  bad = sample();
  bad.erase("t");
  expect_error(call(api, "POST", path, json{{"samples", {bad}}}.dump(), code), 400, "samples[0].t");
  expect_error(call(api, "POST", path, json{{"samples", {sample()}}, {"extra", 1}}.dump(), code), 400, "extra");
  expect_error(call(api, "POST", path, json{{"samples", {sample()}}, {"profile", "toaster"}}.dump(), code), 400, "profile");
  json huge = json::array();
  for (size_t i = 0; i <= capture::kMaxSamplesPerBatch; ++i) huge.push_back(sample());
  expect_error(call(api, "POST", path, json{{"samples", huge}}.dump(), code), 413, "samples");
  expect_error(call(api, "POST", "/api/sessions", R"({"mode": "both"})"), 400, "mode");
  expect_error(call(api, "POST", "/api/sessions", R"({"steps": "some"})"), 400, "steps");
  expect_error(call(api, "POST", "/api/sessions", R"({"weight_kg": -3})"), 400, "weight");
  expect_error(call(api, "POST", "/api/sessions", R"({"sex": "neutral"})"), 400, "sex");
  expect_error(call(api, "POST", "/api/sessions/" + id + "/entries", R"({"weight_kg": "heavy"})", code), 400, "weight");
  expect_error(call(api, "GET", "/api/sessions/s-nope"), 404, "id");
  expect_error(call(api, "POST", "/api/sessions/s-nope/samples", "{}", code), 404, "id");
  expect_error(call(api, "GET", "/api/sessions/" + id + "/export", {}, {}, kHeadset, {{"format", "xml"}}), 400, "format");
  expect_error(call(api, "PUT", "/api/sessions"), 405, "method");
  expect_error(call(api, "GET", "/api/sessions/" + id + "/samples"), 405, "method");
  // Nothing of the refused batches reached the session.
  EXPECT_EQ(body_of(call(api, "GET", "/api/sessions/" + id))["session"]["points"].size(), 0u);
}

TEST(CaptureApi, NumbersTooLargeForADoubleAreA400NamingTheBody) {
  TempDir dir;
  Api api(options_for(dir / "s.db"));
  const auto [id, code] = create(api);
  for (const auto& [path, body] : std::vector<std::pair<std::string, std::string>>{
           {"/api/sessions", R"({"weight_kg": 1e999})"},
           {"/api/sessions/" + id + "/entries", R"({"weight_kg": -1e999})"},
           {"/api/sessions/" + id + "/samples",
            R"({"samples": [{"t": 1e999, "hand": "left", "position": [0, 1, 0], "orientation": [0, 0, 0, 1], "trigger": 0}]})"}}) {
    const ApiResponse r = call(api, "POST", path, body, code);
    expect_error(r, 400, "body");
    const json e = body_of(r)["error"];
    EXPECT_EQ(e["kind"], "invalid_argument") << path;
    EXPECT_NE(e["message"].get<std::string>().find("a number in the request is too large"), std::string::npos) << e;
  }
}

// `caliper serve --capture-profiles` is checked with this before the server starts, loading the
// file as the endpoints do, so a bad file stops the start-up instead of failing requests later.
TEST(CaptureApi, ProfilesFilesAreCheckedAsTheEndpointsLoadThem) {
  TempDir dir;
  test::write_file(dir / "good.json", R"({"profiles": {"test-pen": {"tip_offset_m": [0, 0, 0.1], "label": "Pen"}}})");
  test::write_file(dir / "broken.json", "{not json");
  test::write_file(dir / "far.json", R"({"profiles": {"test-pen": {"tip_offset_m": [0, 0, 2]}}})");
  EXPECT_NO_THROW(check_capture_profiles_file(dir / "good.json"));
  auto kind_of = [](const std::string& path) {
    try {
      check_capture_profiles_file(path);
    } catch (const Error& e) {
      return std::optional<ErrorKind>(e.kind());
    }
    return std::optional<ErrorKind>();
  };
  EXPECT_EQ(kind_of(dir / "missing.json"), ErrorKind::Io);
  EXPECT_EQ(kind_of(dir / "broken.json"), ErrorKind::Format);
  EXPECT_EQ(kind_of(dir / "far.json"), ErrorKind::Format);
  // What the check accepted is what the endpoint serves.
  ApiOptions o = options_for(dir / "s.db");
  o.capture_profiles_file = dir / "good.json";
  Api api(o);
  const ApiResponse r = call(api, "GET", "/api/capture/profiles");
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(body_of(r)["profiles"]["test-pen"]["label"], "Pen");
  // And a file broken after start-up is still reported by the endpoint, as a database format error.
  o.capture_profiles_file = dir / "broken.json";
  Api broken(o);
  const ApiResponse b = call(broken, "GET", "/api/capture/profiles");
  EXPECT_EQ(b.status, 500);
  EXPECT_EQ(body_of(b)["error"]["kind"], "database_format");
}

// The server process dies without closing anything: its Api is not destroyed before a new Api
// opens the same database (so nothing its destructor might flush can help), and the session
// finishes with the values an uninterrupted session gives. `first` is only destroyed at the end
// of the test, after every check: it used to be leaked outright, which LeakSanitizer reports.
TEST(CaptureApi, ANewServerResumesASessionMidway) {
  TempDir dir;
  ScriptedPerson person;
  auto first = std::make_unique<Api>(options_for(dir / "s.db"));
  const auto [id, code] = create(*first);
  SampleScript a(kTouchPlus, 40);
  test::script_floor(a, person);
  a.hold(1, person.head_top, 1.2);
  send(*first, id, code, a);
  // `first` is abandoned here, not destroyed: the state must already be on disk.

  Api second(options_for(dir / "s.db"));
  json s = body_of(call(second, "GET", "/api/sessions/" + id, {}, code))["session"];
  EXPECT_EQ(s["step"]["name"], "stature");
  EXPECT_EQ(s["step"]["repetition"], 2);
  EXPECT_EQ(s["points"].size(), 6u);
  SampleScript b(kTouchPlus, 41);
  b.hold(1, person.head_top, 1.2);
  for (int rep = 0; rep < 2; ++rep) b.hold(0, person.left_fingertip, 1.2, &person.right_fingertip);
  for (int rep = 0; rep < 2; ++rep) b.hold(1, person.crotch, 1.2);
  for (int rep = 0; rep < 2; ++rep) b.hold(1, person.hip_right, 1.2, &person.hip_left);
  for (int rep = 0; rep < 2; ++rep) b.hold(0, person.wrist, 1.2, &person.acromion);
  send(second, id, code, b);
  s = body_of(call(second, "POST", "/api/sessions/" + id + "/entries", R"({"weight_kg": 58, "sex": "female"})", code))["session"];
  EXPECT_EQ(s["state"], "done");
  EXPECT_NEAR(s["measurement_set"]["stature"].get<double>(), person.stature() * 100, 0.25);
  EXPECT_NEAR(s["measurement_set"]["arm_length"].get<double>(), person.arm_length() * 100, 0.1);
  first.reset();  // only now, after `second` has finished the session from the database alone
}

class CaptureHttp : public ::testing::Test {
 protected:
  static void serve(ServerOptions o, const std::function<void(int port)>& body) {
    o.host = "127.0.0.1";
    o.port = 0;
    o.web_root = test::toy_web_root();
    Server srv(o);
    const int port = srv.bind();
    std::thread t([&] { srv.run(); });
    body(port);
    srv.stop();
    t.join();
  }
};

TEST_F(CaptureHttp, ThePairingHeaderTravelsOverHttp) {
  TempDir dir;
  ServerOptions o;
  o.api = options_for(dir / "s.db");
  serve(o, [&](int port) {
    httplib::Client c("127.0.0.1", port);
    auto created = c.Post("/api/sessions", "{}", "application/json");
    ASSERT_TRUE(created);
    ASSERT_EQ(created->status, 201);
    const json j = json::parse(created->body);
    const std::string id = j["session"]["id"], code = j["pairing_code"];
    auto refused = c.Post(("/api/sessions/" + id + "/undo").c_str(), "", "application/json");
    ASSERT_TRUE(refused);
    EXPECT_EQ(refused->status, 403);
    httplib::Headers h = {{"X-Caliper-Pairing", code}};
    auto ok = c.Post(("/api/sessions/" + id + "/undo").c_str(), h, "", "application/json");
    ASSERT_TRUE(ok);
    EXPECT_EQ(ok->status, 200) << ok->body;
  });
}

TEST_F(CaptureHttp, HttpsWithAGeneratedCertificate) {
  TempDir dir;
  const CertificateFiles files = ensure_self_signed_certificate(dir / "data", {"localhost", "127.0.0.1"});
  EXPECT_TRUE(files.created);
  EXPECT_TRUE(std::filesystem::exists(files.cert_file));
  EXPECT_EQ(std::filesystem::status(files.key_file).permissions() & std::filesystem::perms::others_read, std::filesystem::perms::none);
  EXPECT_FALSE(ensure_self_signed_certificate(dir / "data", {"localhost"}).created);  // reused
  ServerOptions o;
  o.api = options_for(dir / "s.db");
  o.https = true;
  o.cert_file = files.cert_file;
  o.key_file = files.key_file;
  serve(o, [&](int port) {
    httplib::SSLClient c("127.0.0.1", port);
    c.set_ca_cert_path(files.cert_file.c_str());
    c.enable_server_certificate_verification(true);
    auto r = c.Get("/api/capture/profiles");
    ASSERT_TRUE(r) << httplib::to_string(r.error());
    EXPECT_EQ(r->status, 200);
    // Plain HTTP to the HTTPS port gets no answer.
    httplib::Client plain("127.0.0.1", port);
    plain.set_read_timeout(2, 0);
    auto p = plain.Get("/api/capture/profiles");
    EXPECT_TRUE(!p || p->status != 200);
  });
  ServerOptions broken = o;
  broken.key_file = dir / "missing-key.pem";
  EXPECT_THROW(Server s(broken), caliper::Error);
}

}  // namespace
}  // namespace caliper::server
