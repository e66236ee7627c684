// Internal: checked reads from untrusted JSON documents (files a user hands Caliper: real → virtual
// maps, MakeHuman rigs). Each throws Error(Format) naming the document and the value's path in
// it ("maps.hip_breadth.pairs"), never nlohmann's type_error or undefined behaviour (a missing key
// read through a const object, get<int>() of 1e300).
#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

namespace caliper::detail {

// Where a value sits: the document (a file path or a description) and the path inside it.
struct JsonPlace {
  std::string document;
  std::string path;  // dotted, empty for the document itself
  JsonPlace operator/(const std::string& key) const;
  [[noreturn]] void fail(const std::string& what) const;  // Error(Format, field = path)
};

// `object`'s member `key`, where `object` is the value at `place`: it must be a JSON object and
// hold the key.
const nlohmann::json& json_require(const nlohmann::json& object, const std::string& key, const JsonPlace& place);
// The same, or nullptr when the key is absent or null.
const nlohmann::json* json_find(const nlohmann::json& object, const std::string& key, const JsonPlace& place);

std::string json_string(const nlohmann::json& value, const JsonPlace& place);
double json_number(const nlohmann::json& value, const JsonPlace& place);  // finite
// An integer in [lo, hi]; integral floats (20.0) are accepted, 1e300 is out of range, 2.5 is not one.
std::int64_t json_integer(const nlohmann::json& value, const JsonPlace& place, std::int64_t lo, std::int64_t hi);

// Optional members with a fallback when absent or null.
double json_number_or(const nlohmann::json& object, const std::string& key, double fallback, const JsonPlace& place);
std::int64_t json_integer_or(const nlohmann::json& object, const std::string& key, std::int64_t fallback,
                             const JsonPlace& place, std::int64_t lo, std::int64_t hi);
std::string json_string_or(const nlohmann::json& object, const std::string& key, const std::string& fallback,
                           const JsonPlace& place);

}  // namespace caliper::detail
