// Invalid UTF-8 in request bodies (audit, docs/reliability.md): it once gave a 500, because error
// messages quote the input and nlohmann's dump() threw inside the handlers' catch blocks, so the
// exception escaped Api::handle, documented as never throwing. Every POST endpoint of both APIs
// must now answer 400 naming the body, and an error message quoting bad bytes must still dump.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "api.h"
#include "api_fixture.h"
#include "capture_api.h"
#include "temp_files.h"

namespace caliper::server {
namespace {

using nlohmann::json;

ApiRequest post(const std::string& path, const std::string& body, const std::string& code = {}) {
  ApiRequest r;
  r.method = "POST";
  r.path = path;
  r.body = body;
  r.content_type = "application/json";
  r.remote_address = "127.0.0.1";
  if (!code.empty()) r.headers["x-caliper-pairing"] = code;
  return r;
}

// Lone continuation byte, truncated sequence, overlong '/', UTF-16 surrogate, beyond U+10FFFF,
// inside JSON strings, as a key, outside any string, and as a CSV measurement set.
const std::vector<std::string>& bad_bodies() {
  static const std::vector<std::string> bodies = {
      "\xff",
      "{\"sex\": \"fem\x80le\"}",
      "{\"measurements\": {\"stature\xc3\": 170}}",
      "{\"model\": \"toy\xc0\xaf\"}",
      "{\"label\": \"\xed\xa0\x80\"}",
      "{\"weight_kg\": 60, \"note\": \"\xf4\x90\x80\x80\"}",
      "{\"samples\": \xfe}",
      "stature,170\nweigh\xe9,60\n",
  };
  return bodies;
}

void expect_utf8_refusal(const ApiResponse& r, const std::string& where) {
  EXPECT_GE(r.status, 400) << where << ": " << r.body;
  EXPECT_LT(r.status, 500) << where << ": " << r.body;
  const json j = json::parse(r.body, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << where << ": not JSON: " << r.body;
  EXPECT_EQ(j["error"]["field"], "body") << where << ": " << r.body;
  EXPECT_NE(j["error"]["message"].get<std::string>().find("UTF-8"), std::string::npos) << where << ": " << r.body;
}

TEST(InvalidUtf8, EveryPostEndpointOfBothApisAnswers400AndNeverThrows) {
  test::TempDir dir;
  ApiOptions options;
  options.models_dir = test::toy_models_dir();
  options.default_model = "toy";
  options.sessions_database = dir / "sessions.db";
  const Api api(options);
  // A real session with its pairing code, so its endpoints get as far as reading the body.
  const ApiResponse created = api.handle(post("/api/sessions", "{}"));
  ASSERT_EQ(created.status, 201) << created.body;
  const json session = json::parse(created.body);
  const std::string id = session["session"]["id"], code = session["pairing_code"];
  const std::string s = "/api/sessions/" + id;

  const std::vector<std::string> desktop = {"/api/avatar", "/api/export/glb", "/api/export/obj", "/api/export/report",
                                            "/api/measurement-set/import", "/api/measurement-set/export"};
  const std::vector<std::string> capture = {"/api/sessions", s + "/samples", s + "/undo", s + "/redo", s + "/entries"};
  const CaptureApi capture_api(CaptureApiOptions{dir / "sessions.db", {}, false, {}, {}, {}});
  for (const auto& body : bad_bodies()) {
    for (const auto& path : desktop) {
      ApiResponse r;
      EXPECT_NO_THROW(r = api.handle(post(path, body))) << path;
      expect_utf8_refusal(r, path);
    }
    for (const auto& path : capture) {
      ApiResponse r;
      EXPECT_NO_THROW(r = api.handle(post(path, body, code))) << path;
      expect_utf8_refusal(r, path);
      EXPECT_NO_THROW(r = capture_api.handle(post(path, body, code))) << "CaptureApi " << path;
      expect_utf8_refusal(r, "CaptureApi " + path);
    }
  }
  // The session is still there and readable.
  const ApiResponse after = api.handle(ApiRequest{"GET", s, {}, {}, {}, {}, "127.0.0.1", "127.0.0.1"});
  ASSERT_EQ(after.status, 200) << after.body;
}

// The one place responses are dumped: a message quoting invalid bytes becomes U+FFFD, not an
// exception.
TEST(InvalidUtf8, AnErrorMessageQuotingBadBytesStillDumps) {
  ApiResponse r;
  ASSERT_NO_THROW(r = error_response(400, "unknown measurement 'stat\xff\xc3'", "stat\xff", "invalid_argument"));
  const json j = json::parse(r.body);
  EXPECT_EQ(j["error"]["message"], "unknown measurement 'stat\xef\xbf\xbd\xef\xbf\xbd'");
  EXPECT_EQ(r.status, 400);
}

}  // namespace
}  // namespace caliper::server
