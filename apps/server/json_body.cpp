#include "json_body.h"

#include <cmath>

#include "caliper/errors.h"
#include "caliper/utf8.h"

namespace caliper::server {

void require_utf8(const std::string& text, const std::string& what) {
  const std::size_t bad = invalid_utf8_offset(text);
  if (bad != std::string_view::npos)
    throw Error(ErrorKind::InvalidArgument,
                what + " is not valid UTF-8 (byte " + std::to_string(bad) + " of " + std::to_string(text.size()) +
                    "); send UTF-8 text",
                "body");
}

std::string dump_json(const nlohmann::ordered_json& j, int indent) {
  return j.dump(indent, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

ApiResponse json_response(const nlohmann::ordered_json& j, int status) {
  ApiResponse r;
  r.status = status;
  r.body = dump_json(j);
  return r;
}

double round_to(double v, double step) {
  const double inverse = std::round(1.0 / step);
  return std::round(v * inverse) / inverse;
}

nlohmann::ordered_json parse_json_object(const std::string& text, const std::string& what) {
  nlohmann::ordered_json j;
  try {
    j = nlohmann::ordered_json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(ErrorKind::InvalidArgument, what + " is not valid JSON: " + e.what(), "body");
  } catch (const nlohmann::json::out_of_range&) {
    // nlohmann's "number overflow" (e.g. 1e999): the client's mistake, but the parser does not
    // say where, so the field can only be the body.
    throw Error(ErrorKind::InvalidArgument,
                "a number in the request is too large (beyond ±1.8e308, the largest a double holds); "
                "check every value in " + what,
                "body");
  }
  if (!j.is_object()) throw Error(ErrorKind::InvalidArgument, what + " must be a JSON object", "body");
  return j;
}

}  // namespace caliper::server
