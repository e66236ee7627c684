// Calling the API in-process, as the HTTP server does, for the API tests: one request builder,
// the JSON body of an answer, and the check that an answer is an error naming a field.
#pragma once
#include <gtest/gtest.h>

#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "api.h"
#include "api_fixture.h"

namespace caliper::server::test_calls {

// Where requests come from: the desktop tool runs on the server's machine, a headset on the LAN.
inline constexpr const char* kDesktop = "127.0.0.1";
inline constexpr const char* kHeadset = "192.168.1.30";

// The API over the toy models (api_fixture.h), its sessions kept in `database`.
inline ApiOptions options_for(const std::string& database) {
  ApiOptions o;
  o.models_dir = caliper::test::toy_models_dir();
  o.default_model = "toy";
  o.sessions_database = database;
  return o;
}

// One request; `code` is sent as the pairing header when given.
inline ApiResponse call(const Api& api, const std::string& method, const std::string& path, const std::string& body = {},
                        const std::string& code = {}, const std::string& remote = kHeadset,
                        std::map<std::string, std::string> query = {}) {
  ApiRequest r;
  r.method = method;
  r.path = path;
  r.remote_address = remote;
  r.body = body;
  r.query = std::move(query);
  r.content_type = "application/json";
  if (!code.empty()) r.headers["x-caliper-pairing"] = code;
  return api.handle(r);
}

inline nlohmann::json body_of(const ApiResponse& r) { return nlohmann::json::parse(r.body); }

// Expects a JSON error with `status` naming `field` (no field when empty) and saying something;
// returns the error object.
inline nlohmann::json expect_error(const ApiResponse& r, int status, const std::string& field) {
  EXPECT_EQ(r.status, status) << r.body;
  EXPECT_EQ(r.content_type, "application/json");
  const nlohmann::json j = nlohmann::json::parse(r.body, nullptr, false);
  if (!j.is_object() || !j.contains("error")) {
    ADD_FAILURE() << "not a JSON error: " << r.body;
    return {};
  }
  const nlohmann::json& e = j["error"];
  EXPECT_TRUE(e["message"].is_string() && !e["message"].get<std::string>().empty()) << r.body;
  if (field.empty()) EXPECT_TRUE(e["field"].is_null()) << r.body;
  else EXPECT_EQ(e["field"], field) << r.body;
  return e;
}

}  // namespace caliper::server::test_calls
