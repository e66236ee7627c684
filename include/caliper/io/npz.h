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

// Parses one .npy document. `name` is used in error messages. Throws Error(Format).
Array parse_npy(const std::string& bytes, const std::string& name);
std::string write_npy_f64(const std::vector<double>& values, const std::vector<std::int64_t>& shape);
std::string write_npy_i64(const std::vector<std::int64_t>& values, const std::vector<std::int64_t>& shape);
std::string write_npy_unicode(const std::string& utf8_text);  // a 0-d '<U' array
// An array of strings ('<U' as wide as the longest); throws Error(InvalidArgument) on bad UTF-8.
std::string write_npy_unicode_array(const std::vector<std::string>& utf8_texts,
                                    const std::vector<std::int64_t>& shape);

// Whole archive: array name (without ".npy") → array. Throws Error(Io) if the file cannot be
// opened, Error(Format) if it is not a zip or an entry is malformed or truncated.
std::map<std::string, Array> read_npz(const std::string& path);

// Writes entries (name → .npy bytes) as a deflated zip. Entries are written in name order with a
// fixed timestamp so the same arrays give the same bytes. Throws Error(Io).
void write_npz(const std::string& path, const std::map<std::string, std::string>& npy_entries);

}  // namespace caliper::npz
