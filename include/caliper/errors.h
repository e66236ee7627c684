// Caliper's error type. Trust boundaries (files, CLI arguments, HTTP bodies) throw
// caliper::Error with a kind, the field and whose input it was, so the CLI can map it to an exit
// code and the server to a 4xx (the caller's input) or a 500 (the installation's own files).
// The core asserts programmer errors; it never exits or prints.
#pragma once
#include <stdexcept>
#include <string>
#include <utility>

namespace caliper {

enum class ErrorKind {
  InvalidArgument,  // a value is NaN, negative, absurd or of the wrong kind (names the field)
  OutOfRange,       // a measurement outside its accepted range (names the field and the range)
  Io,               // a file cannot be opened, read or written
  Format,           // a file or document is malformed, truncated or inconsistent
  Unsupported,      // a valid request Caliper cannot serve (e.g. unknown measurement for a model)
};

// Whose input failed. A reader cannot know (the same model reader is fed `--model my.npz` and the
// models folder's own files), so errors start as the caller's and the code that opened an
// installation file says so with `installation_input` below.
enum class ErrorOrigin {
  Caller,        // values, files the caller named, request bodies: CLI exit 3–4, HTTP 4xx
  Installation,  // Caliper's own files (models found by name, the server's profiles and
                 // database): CLI exit 5, HTTP 500 with no file-system path in the body
};

class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, std::string message, std::string field = {}, ErrorOrigin origin = ErrorOrigin::Caller)
      : std::runtime_error(std::move(message)), kind_(kind), origin_(origin), field_(std::move(field)) {}
  ErrorKind kind() const noexcept { return kind_; }
  ErrorOrigin origin() const noexcept { return origin_; }
  bool from_installation() const noexcept { return origin_ == ErrorOrigin::Installation; }
  // The offending field (measurement name, CLI option, file array name), or empty.
  const std::string& field() const noexcept { return field_; }

  // The same error (kind and origin kept) with another message or field, for a caller that adds
  // context: `throw e.restated("--model: " + std::string(e.what()), "--model");`
  Error restated(std::string message, std::string field) const { return Error(kind_, std::move(message), std::move(field), origin_); }
  // The same error, blamed on `origin`.
  Error from(ErrorOrigin origin) const { return Error(kind_, what(), field_, origin); }

 private:
  ErrorKind kind_;
  ErrorOrigin origin_;
  std::string field_;
};

const char* to_string(ErrorKind kind);
const char* to_string(ErrorOrigin origin);  // "caller" | "installation"

// Runs `read` on one of the installation's own inputs — a model found by name in the models
// folder, the server's capture profiles or sessions database — and re-throws any caliper::Error
// from it as the installation's. The origin is decided here, where the input is opened, never in
// the parser:  auto model = installation_input([&] { return load_native_model(path); });
template <class Read>
decltype(auto) installation_input(Read&& read) {
  try {
    return std::forward<Read>(read)();
  } catch (const Error& e) {
    throw e.from(ErrorOrigin::Installation);
  }
}

}  // namespace caliper
