// NumPy .npy/.npz arrays: the native model format (numpy can open it) and SMPL files.
// Reads float32/64, int8–64, uint8–64, bool and unicode ('<U') arrays, either byte order,
// C or Fortran order, stored or deflated. Object arrays ('|O', pickles) are listed but never
// unpickled: reading one throws.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace caliper::npz {

struct Array {
  std::string dtype;              // numpy descr as stored, e.g. "<f8", "<U12", "|O"
  std::vector<std::int64_t> shape;
  std::vector<double> numbers;    // numeric arrays, C order, converted to double
  std::vector<std::string> strings;  // unicode arrays, C order
  bool is_object = false;         // pickled: contents not read
  std::int64_t size() const;      // product of shape (1 for a 0-d array)
};

// Parses one .npy document. `name` is used in error messages. Throws Error(Format), also for
// more values than ReadLimits{}.array_values.
Array parse_npy(const std::string& bytes, const std::string& name);
std::string write_npy_f64(const std::vector<double>& values, const std::vector<std::int64_t>& shape);
std::string write_npy_i64(const std::vector<std::int64_t>& values, const std::vector<std::int64_t>& shape);
std::string write_npy_unicode(const std::string& utf8_text);  // a 0-d '<U' array
// An array of strings ('<U' as wide as the longest); throws Error(InvalidArgument) on bad UTF-8.
std::string write_npy_unicode_array(const std::vector<std::string>& utf8_texts,
                                    const std::vector<std::int64_t>& shape);

// What read_npz may allocate. Every bound is checked before the data it covers is read: an
// entry's size in the zip directory, then its .npy header (values × dtype size must equal that
// size), and the inflated byte count while reading. Defaults come from the largest body model
// Caliper reads, SMPL-X (10,475 vertices; docs/model-format.md "Limits"): its largest array,
// posedirs, holds 10,475 × 3 × 486 = 15.3 M values (122 MB as float64), shapedirs with 400
// directions 12.6 M, the whole file about 29 M values (235 MB as float64). Each bound is about
// twice that; values are held as doubles, so an archive costs at most 8 × archive_values bytes.
struct ReadLimits {
  std::int64_t array_values = std::int64_t{1} << 25;     // 33.5 M values in one array
  std::uint64_t entry_bytes = std::uint64_t{1} << 28;    // 256 MiB: one uncompressed .npy entry
  std::int64_t archive_values = std::int64_t{1} << 26;   // 67 M values in all arrays together
  std::uint64_t archive_bytes = std::uint64_t{1} << 29;  // 512 MiB uncompressed in all entries
  std::int64_t entries = 1024;                           // SMPL-X files hold about 20
};

// Whole archive: array name (without ".npy") → array. Throws Error(Io) if the file cannot be
// opened, Error(Format) if it is not a zip, an entry is malformed or truncated, or the archive
// exceeds `limits` (the message names the array and the limit).
std::map<std::string, Array> read_npz(const std::string& path, const ReadLimits& limits = {});

// Writes entries (name → .npy bytes) as a deflated zip. Entries are written in name order with a
// fixed timestamp so the same arrays give the same bytes. Throws Error(Io).
void write_npz(const std::string& path, const std::map<std::string, std::string>& npy_entries);

}  // namespace caliper::npz
