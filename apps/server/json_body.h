// Parsing of JSON request bodies and writing of JSON responses, shared by api.cpp and
// capture_api.cpp so every endpoint refuses a bad body and writes numbers the same way.
// Server-internal: callers link nlohmann_json privately.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "api.h"

namespace caliper::server {

// Parses `text` as one JSON object; `what` names it in messages ("the request body"). Throws
// caliper::Error(InvalidArgument, field "body") for invalid JSON, a number too large for a
// double, or anything but an object — a 400 `invalid_argument` on every endpoint.
nlohmann::ordered_json parse_json_object(const std::string& text, const std::string& what);

// Throws caliper::Error(InvalidArgument, field "body") naming `what` and the offset of the first
// bad byte unless `text` is valid UTF-8. Both APIs' routers pass every request body here before
// an endpoint parses it or quotes it in a message (a 400 on every endpoint).
void require_utf8(const std::string& text, const std::string& what);

// The JSON text of a response. Never throws: invalid UTF-8 inside strings (text quoted from a
// request into an error message) is written as U+FFFD, so an error response cannot itself fail.
std::string dump_json(const nlohmann::ordered_json& j, int indent = -1);

// A JSON response with the given status.
ApiResponse json_response(const nlohmann::ordered_json& j, int status = 200);

// Rounds to a decimal step (0.1, 1e-4…) so that the JSON shows 178.1, not 178.10000000000002:
// dividing by the integer 1/step gives the double nearest the decimal, multiplying by step not.
double round_to(double v, double step);

}  // namespace caliper::server
