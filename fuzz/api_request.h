// The HTTP fuzzers' input: a request line "METHOD /path?query" (optional header lines
// "name: value"), a blank line, then the body — like HTTP, without the transport. "{session}" in
// the path and "{code}" in a header stand for a live capture session and its pairing code, so
// mutations reach the session endpoints instead of stopping at 404. Oracle for every response
// (docs/api.md): a status in [100, 500) — never a 5xx, since the server's own files are fine
// here — and a JSON body whenever the content type says JSON.
#pragma once
#include <nlohmann/json.hpp>

#include <string>

#include "api.h"
#include "fuzz_support.h"

namespace caliper::fuzz {

inline void replace_all(std::string& s, const std::string& from, const std::string& to) {
  for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size())) s.replace(at, from.size(), to);
}

inline server::ApiRequest parse_request(const std::string& input, const std::string& session, const std::string& code) {
  server::ApiRequest r;
  r.remote_address = r.local_address = "127.0.0.1";  // the experimenter's desktop: every endpoint is open
  size_t line_end = input.find('\n');
  const std::string request_line = input.substr(0, line_end);
  const size_t space = request_line.find(' ');
  r.method = request_line.substr(0, space);
  std::string target = space == std::string::npos ? "/" : request_line.substr(space + 1);
  replace_all(target, "{session}", session);
  const size_t question = target.find('?');
  r.path = target.substr(0, question);
  if (question != std::string::npos) {
    std::string query = target.substr(question + 1);
    for (size_t at = 0; at <= query.size();) {
      const size_t amp = std::min(query.find('&', at), query.size());
      const std::string pair = query.substr(at, amp - at);
      const size_t eq = pair.find('=');
      r.query[pair.substr(0, eq)] = eq == std::string::npos ? "" : pair.substr(eq + 1);
      at = amp + 1;
    }
  }
  while (line_end != std::string::npos) {  // header lines up to the blank one
    const size_t next = input.find('\n', line_end + 1);
    const std::string line = input.substr(line_end + 1, next == std::string::npos ? std::string::npos : next - line_end - 1);
    line_end = next;
    if (line.empty()) break;
    const size_t colon = line.find(": ");
    std::string name = line.substr(0, colon), value = colon == std::string::npos ? "" : line.substr(colon + 2);
    for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    replace_all(value, "{code}", code);
    if (name == "content-type") r.content_type = value;
    r.headers[name] = value;
  }
  r.body = line_end == std::string::npos ? "" : input.substr(line_end + 1);
  return r;
}

inline void check_response(const server::ApiResponse& response, const server::ApiRequest& request) {
  const std::string what = request.method + " " + request.path + " -> " + std::to_string(response.status) + " " +
                           response.body.substr(0, 400);
  check(response.status >= 100 && response.status < 500, "status out of [100, 500): " + what);
  if (response.content_type.rfind("application/json", 0) == 0)
    check(!nlohmann::json::parse(response.body, nullptr, false).is_discarded(), "a JSON response that is not JSON: " + what);
}

// A live capture session created through `api` (both handlers serve POST /api/sessions): what
// "{session}" and "{code}" in the inputs stand for.
struct LiveSession {
  std::string id, code;
};
template <class Handler>
LiveSession create_session(const Handler& api) {
  server::ApiRequest create{"POST", "/api/sessions", {}, "{}", "application/json", {}, "127.0.0.1", "127.0.0.1"};
  const auto created = nlohmann::json::parse(api.handle(create).body);
  return {created["session"]["id"], created["pairing_code"]};
}

// One fuzz input through `api`, checked by check_response.
template <class Handler>
int handle_input(const Handler& api, const LiveSession& session, const uint8_t* data, size_t size) {
  const server::ApiRequest request = parse_request(as_string(data, size), session.id, session.code);
  check_response(api.handle(request), request);
  return 0;
}

}  // namespace caliper::fuzz
