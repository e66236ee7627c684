#include "json_read.h"

#include <cmath>

#include "caliper/errors.h"

namespace caliper::detail {

using nlohmann::json;

JsonPlace JsonPlace::operator/(const std::string& key) const { return {document, path.empty() ? key : path + "." + key}; }

void JsonPlace::fail(const std::string& what) const {
  throw Error(ErrorKind::Format, document + ": " + (path.empty() ? std::string("the document") : path) + " " + what, path);
}

const json* json_find(const json& object, const std::string& key, const JsonPlace& place) {
  if (!object.is_object()) place.fail(std::string("must be a JSON object, found ") + object.type_name());
  const auto it = object.find(key);
  return it == object.end() || it->is_null() ? nullptr : &*it;
}

const json& json_require(const json& object, const std::string& key, const JsonPlace& place) {
  const json* v = json_find(object, key, place);
  if (!v) (place / key).fail("is missing");
  return *v;
}

std::string json_string(const json& value, const JsonPlace& place) {
  if (!value.is_string()) place.fail(std::string("must be a string, found ") + value.type_name());
  return value.get<std::string>();
}

double json_number(const json& value, const JsonPlace& place) {
  if (!value.is_number()) place.fail(std::string("must be a number, found ") + value.type_name());
  const double v = value.get<double>();
  if (!std::isfinite(v)) place.fail("must be a finite number");
  return v;
}

std::int64_t json_integer(const json& value, const JsonPlace& place, std::int64_t lo, std::int64_t hi) {
  std::string range = "[";  // appended piecewise: GCC 12 warns falsely on operator+ chains
  range.append(std::to_string(lo)).append(", ").append(std::to_string(hi)).append("]");
  if (!value.is_number()) place.fail("must be an integer in " + range + ", found " + value.type_name());
  // Compared as doubles before any conversion: casting 1e300 (or 2^64 − 1) to an integer is
  // undefined or wraps.
  const double v = value.get<double>();
  if (!(v >= static_cast<double>(lo) && v <= static_cast<double>(hi)) || v != std::floor(v))
    place.fail("must be an integer in " + range + ", got " + value.dump());
  if (value.is_number_unsigned()) return static_cast<std::int64_t>(value.get<std::uint64_t>());
  if (value.is_number_integer()) return value.get<std::int64_t>();
  return static_cast<std::int64_t>(v);
}

double json_number_or(const json& object, const std::string& key, double fallback, const JsonPlace& place) {
  const json* v = json_find(object, key, place);
  return v ? json_number(*v, place / key) : fallback;
}

std::int64_t json_integer_or(const json& object, const std::string& key, std::int64_t fallback, const JsonPlace& place,
                             std::int64_t lo, std::int64_t hi) {
  const json* v = json_find(object, key, place);
  return v ? json_integer(*v, place / key, lo, hi) : fallback;
}

std::string json_string_or(const json& object, const std::string& key, const std::string& fallback, const JsonPlace& place) {
  const json* v = json_find(object, key, place);
  return v ? json_string(*v, place / key) : fallback;
}

}  // namespace caliper::detail
