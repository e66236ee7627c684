// Internal: the current time as ISO 8601 UTC text, as sessions and points are stamped.
#pragma once
#include <ctime>
#include <string>

namespace caliper::capture::detail {

inline std::string now_iso() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace caliper::capture::detail
