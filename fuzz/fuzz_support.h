// Shared by the fuzz targets (docs/reliability.md "Fuzzing"). A target hands its input to one
// gate. The gate may refuse the input with caliper::Error, the library's one exception type;
// anything else escaping a target is a finding (libFuzzer reports the uncaught exception as a
// crash), and so is a failed oracle: check() aborts, so libFuzzer saves the input.
#pragma once
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <string_view>

#include "caliper/errors.h"

namespace caliper::fuzz {

inline std::string as_string(const uint8_t* data, size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Runs the gate: true if it accepted the input, false if it refused it with caliper::Error.
template <class Gate>
bool accepts(Gate&& gate) {
  try {
    gate();
    return true;
  } catch (const Error&) {
    return false;
  }
}

// An oracle: a property every accepted input must have.
inline void check(bool holds, const std::string& what) {
  if (holds) return;
  std::fprintf(stderr, "oracle failed: %s\n", what.c_str());
  std::abort();
}

// A folder of this process's own for the readers that take a path; removed at exit.
inline const std::filesystem::path& scratch_dir() {
  struct Dir {
    std::filesystem::path path;
    Dir() {
      path = std::filesystem::temp_directory_path() / ("caliper-fuzz-" + std::to_string(::getpid()));
      std::filesystem::create_directories(path);
    }
    ~Dir() {
      std::error_code ec;
      std::filesystem::remove_all(path, ec);
    }
  };
  static const Dir dir;
  return dir.path;
}

// Writes `bytes` to `name` (a relative path) in the scratch folder and returns the full path.
inline std::string write_scratch(const std::string& name, std::string_view bytes) {
  const std::filesystem::path path = scratch_dir() / name;
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path.string();
}

// The model fuzzer's input format: an .npz's entries as one stream the mutator can work on, each
// entry a line "--npy NAME" followed by its .npy bytes. The target zips them (npz::write_npz), so
// mutations reach the model checks instead of stopping at the zip's checksums.
constexpr std::string_view kEntryMarker = "--npy ";

inline std::map<std::string, std::string> split_entries(std::string_view input) {
  std::map<std::string, std::string> entries;
  size_t at = input.find(kEntryMarker);
  while (at != std::string_view::npos) {
    const size_t name_start = at + kEntryMarker.size();
    const size_t name_end = input.find('\n', name_start);
    if (name_end == std::string_view::npos) break;
    size_t next = input.find(std::string("\n") + std::string(kEntryMarker), name_end);
    const size_t data_end = next == std::string_view::npos ? input.size() : next;
    entries[std::string(input.substr(name_start, name_end - name_start))] =
        std::string(input.substr(name_end + 1, data_end - name_end - 1));
    at = next == std::string_view::npos ? next : next + 1;
  }
  return entries;
}

inline std::string join_entries(const std::map<std::string, std::string>& entries) {
  std::string out;
  for (const auto& [name, bytes] : entries) {
    if (!out.empty()) out += '\n';
    out.append(kEntryMarker).append(name).append("\n").append(bytes);
  }
  return out;
}

}  // namespace caliper::fuzz
