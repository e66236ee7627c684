// Parsing of JSON request bodies, shared by api.cpp and capture_api.cpp so every endpoint refuses
// a bad body the same way. Server-internal: callers link nlohmann_json privately.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

namespace caliper::server {

// Parses `text` as one JSON object; `what` names it in messages ("the request body"). Throws
// caliper::Error(InvalidArgument, field "body") for invalid JSON, a number too large for a
// double, or anything but an object — a 400 `invalid_argument` on every endpoint.
nlohmann::ordered_json parse_json_object(const std::string& text, const std::string& what);

}  // namespace caliper::server
