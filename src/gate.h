// The last line of every gate for untrusted input (model files, measurement sets, ANSUR CSV,
// real → virtual maps, MakeHuman assets, controller profiles; docs/reliability.md): the reader's
// own caliper::Error passes through unchanged, and any other exception — a bug the reader missed
// (an nlohmann type_error, std::bad_alloc, a filesystem_error) — becomes Error(Format) naming the
// input, so callers only ever see the library's errors.
#pragma once
#include <new>
#include <stdexcept>
#include <string>
#include <utility>

#include "caliper/errors.h"

namespace caliper {

// `input` names the input for the message ("'f.npz'", "measurement set"); `field` is the error's field.
template <class Read>
decltype(auto) gate(const std::string& input, const std::string& field, Read&& read) {
  try {
    return std::forward<Read>(read)();
  } catch (const Error&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw Error(ErrorKind::Format, input + ": holds more than this machine can allocate", field);
  } catch (const std::exception& e) {
    throw Error(ErrorKind::Format, input + ": malformed (" + e.what() + ")", field);
  }
}

}  // namespace caliper
