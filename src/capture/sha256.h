// SHA-256 (FIPS 180-4), internal to the capture stage: pairing codes are stored salted and hashed.
#pragma once
#include <string>

namespace caliper::capture::detail {

// Lower-case hex digest of `data`.
std::string sha256_hex(const std::string& data);

}  // namespace caliper::capture::detail
