#include "caliper/errors.h"

namespace caliper {

const char* to_string(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::InvalidArgument: return "invalid_argument";
    case ErrorKind::OutOfRange: return "out_of_range";
    case ErrorKind::Io: return "io";
    case ErrorKind::Format: return "format";
    case ErrorKind::Unsupported: return "unsupported";
  }
  return "unknown";
}

const char* to_string(ErrorOrigin origin) {
  return origin == ErrorOrigin::Installation ? "installation" : "caller";
}

}  // namespace caliper
