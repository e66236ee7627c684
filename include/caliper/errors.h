// Caliper's error type. Trust boundaries (files, CLI arguments, HTTP bodies) throw
// caliper::Error with a kind, so the CLI can map it to an exit code and the server to a 4xx.
// The core asserts programmer errors; it never exits or prints.
#pragma once
#include <stdexcept>
#include <string>

namespace caliper {

enum class ErrorKind {
  InvalidArgument,  // a value is NaN, negative, absurd or of the wrong kind (names the field)
  OutOfRange,       // a measurement outside its accepted range (names the field and the range)
  Io,               // a file cannot be opened, read or written
  Format,           // a file or document is malformed, truncated or inconsistent
  Unsupported,      // a valid request Caliper cannot serve (e.g. unknown measurement for a model)
};

class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, std::string message, std::string field = {})
      : std::runtime_error(std::move(message)), kind_(kind), field_(std::move(field)) {}
  ErrorKind kind() const noexcept { return kind_; }
  // The offending field (measurement name, CLI option, file array name), or empty.
  const std::string& field() const noexcept { return field_; }

 private:
  ErrorKind kind_;
  std::string field_;
};

const char* to_string(ErrorKind kind);

}  // namespace caliper
