// NumPy .npy / .npz reading and writing.
// Format: numpy's NEP 1 (".npy" v1.0/2.0/3.0: magic "\x93NUMPY", version, header length, a
// Python-literal dict header padded to 64 bytes, then raw data); ".npz" is a zip of .npy files.
// Everything read here is untrusted: every length is checked against the bytes actually present
// before anything is allocated, so a truncated or hostile file gives Error(Format), never a crash.
#include "caliper/io/npz.h"

#include <zip.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <limits>
#include <memory>

#include "caliper/errors.h"
#include "gate.h"
#include "caliper/utf8.h"

namespace caliper::npz {

std::int64_t Array::size() const {
  std::int64_t n = 1;
  for (std::int64_t d : shape) n *= d;
  return n;
}

namespace {

constexpr char kMagic[] = "\x93NUMPY";
constexpr std::size_t kMagicSize = 6;
// A shape dimension beyond this is a corrupt header (it also keeps the products below in range);
// ReadLimits bounds the values actually allocated.
constexpr std::int64_t kMaxDimension = std::int64_t{1} << 40;
constexpr std::size_t kMaxHeaderSize = 1 << 20;

[[noreturn]] void bad(const std::string& name, const std::string& what) {
  throw Error(ErrorKind::Format, "array '" + name + "': " + what, name);
}

// ---- header dict: {'descr': '<f8', 'fortran_order': False, 'shape': (6890, 3), } ----

struct Header {
  std::string descr;
  bool fortran_order = false;
  bool has_descr = false, has_order = false, has_shape = false;
  std::vector<std::int64_t> shape;
};

class HeaderParser {
 public:
  HeaderParser(const std::string& text, const std::string& name) : s_(text), name_(name) {}

  Header parse() {
    Header h;
    skip_space();
    expect('{');
    while (true) {
      skip_space();
      if (peek() == '}') { ++i_; break; }
      const std::string key = parse_string();
      skip_space();
      expect(':');
      skip_space();
      if (key == "descr") {
        // A list here is a structured dtype (records): not something a model file contains.
        if (peek() != '\'' && peek() != '"') bad(name_, "structured dtypes are not supported");
        h.descr = parse_string();
        h.has_descr = true;
      } else if (key == "fortran_order") {
        h.fortran_order = parse_bool();
        h.has_order = true;
      } else if (key == "shape") {
        h.shape = parse_shape();
        h.has_shape = true;
      } else {
        bad(name_, "unexpected header key '" + key + "'");
      }
      skip_space();
      if (peek() == ',') { ++i_; continue; }
      skip_space();
      if (peek() == '}') { ++i_; break; }
      bad(name_, "malformed header dict");
    }
    if (!h.has_descr || !h.has_order || !h.has_shape)
      bad(name_, "header lacks one of 'descr', 'fortran_order', 'shape'");
    return h;
  }

 private:
  char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
  void skip_space() {
    while (i_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[i_]))) ++i_;
  }
  void expect(char c) {
    if (peek() != c) bad(name_, std::string("malformed header: expected '") + c + "'");
    ++i_;
  }
  std::string parse_string() {
    const char q = peek();
    if (q != '\'' && q != '"') bad(name_, "malformed header: expected a quoted string");
    ++i_;
    std::string out;
    while (i_ < s_.size() && s_[i_] != q) out += s_[i_++];
    if (i_ >= s_.size()) bad(name_, "malformed header: unterminated string");
    ++i_;
    return out;
  }
  bool parse_bool() {
    if (s_.compare(i_, 4, "True") == 0) { i_ += 4; return true; }
    if (s_.compare(i_, 5, "False") == 0) { i_ += 5; return false; }
    bad(name_, "malformed header: fortran_order must be True or False");
  }
  std::vector<std::int64_t> parse_shape() {
    expect('(');
    std::vector<std::int64_t> shape;
    while (true) {
      skip_space();
      if (peek() == ')') { ++i_; break; }
      if (!std::isdigit(static_cast<unsigned char>(peek()))) bad(name_, "malformed header: bad shape");
      std::int64_t v = 0;
      while (std::isdigit(static_cast<unsigned char>(peek()))) {
        v = v * 10 + (s_[i_++] - '0');
        if (v > kMaxDimension) bad(name_, "shape dimension too large");
      }
      if (peek() == 'L') ++i_;  // Python 2 longs in headers written by old numpy
      shape.push_back(v);
      if (shape.size() > 32) bad(name_, "more than 32 dimensions");
      skip_space();
      if (peek() == ',') { ++i_; continue; }
      skip_space();
      if (peek() == ')') { ++i_; break; }
      bad(name_, "malformed header: bad shape");
    }
    return shape;
  }

  const std::string& s_;
  const std::string& name_;
  std::size_t i_ = 0;
};

// ---- dtype ----

enum class Kind { Float, Int, UInt, Bool, Unicode, Bytes, Object };

struct DType {
  Kind kind = Kind::Float;
  bool big_endian = false;
  std::size_t item_size = 0;  // bytes per element
};

DType parse_dtype(const std::string& descr, const std::string& name) {
  if (descr.size() < 2) bad(name, "unsupported dtype '" + descr + "'");
  DType t;
  const char order = descr[0];
  if (order == '>') t.big_endian = true;
  else if (order != '<' && order != '|' && order != '=') bad(name, "unsupported dtype '" + descr + "'");
  const char kind = descr[1];
  const std::string digits = descr.substr(2);
  if (kind == 'O') {
    t.kind = Kind::Object;
    return t;
  }
  std::size_t count = 0;
  if (digits.empty() || digits.size() > 6 || !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    bad(name, "unsupported dtype '" + descr + "'");
  count = std::stoul(digits);
  switch (kind) {
    case 'f':
      if (count != 4 && count != 8) bad(name, "unsupported float size in dtype '" + descr + "'");
      t.kind = Kind::Float;
      t.item_size = count;
      break;
    case 'i':
    case 'u':
      if (count != 1 && count != 2 && count != 4 && count != 8) bad(name, "unsupported integer dtype '" + descr + "'");
      t.kind = kind == 'i' ? Kind::Int : Kind::UInt;
      t.item_size = count;
      break;
    case 'b':
      if (count != 1) bad(name, "unsupported bool dtype '" + descr + "'");
      t.kind = Kind::Bool;
      t.item_size = 1;
      break;
    case 'U':
      if (count < 1) bad(name, "unicode dtype with zero length");
      t.kind = Kind::Unicode;
      t.item_size = 4 * count;
      break;
    case 'S':
      if (count < 1) bad(name, "bytes dtype with zero length");
      t.kind = Kind::Bytes;
      t.item_size = count;
      break;
    default:
      bad(name, "unsupported dtype '" + descr + "'");
  }
  return t;
}

std::uint64_t load_uint(const unsigned char* p, std::size_t n, bool big_endian) {
  std::uint64_t v = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t idx = big_endian ? k : n - 1 - k;
    v = (v << 8) | p[idx];
  }
  return v;
}

double decode_number(const unsigned char* p, const DType& t) {
  const std::uint64_t bits = load_uint(p, t.item_size, t.big_endian);
  switch (t.kind) {
    case Kind::Float:
      if (t.item_size == 4) {
        const auto b32 = static_cast<std::uint32_t>(bits);
        float f;
        std::memcpy(&f, &b32, 4);
        return f;
      } else {
        double d;
        std::memcpy(&d, &bits, 8);
        return d;
      }
    case Kind::Int: {
      // Sign-extend from item_size bytes.
      const unsigned shift = static_cast<unsigned>(64 - 8 * t.item_size);
      const auto s = static_cast<std::int64_t>(bits << shift) >> shift;
      return static_cast<double>(s);
    }
    case Kind::UInt: return static_cast<double>(bits);
    case Kind::Bool: return bits != 0 ? 1.0 : 0.0;
    default: return 0;
  }
}

void append_utf8(std::string& out, std::uint32_t cp) {
  if (cp < 0x80) {
    out += static_cast<char>(cp);
  } else if (cp < 0x800) {
    out += static_cast<char>(0xC0 | (cp >> 6));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else if (cp < 0x10000) {
    out += static_cast<char>(0xE0 | (cp >> 12));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  } else {
    out += static_cast<char>(0xF0 | (cp >> 18));
    out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
    out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
    out += static_cast<char>(0x80 | (cp & 0x3F));
  }
}

std::string decode_unicode(const unsigned char* p, const DType& t, const std::string& name) {
  std::string out;
  const std::size_t n = t.item_size / 4;
  std::size_t len = n;
  // numpy pads short strings with NUL code points at the end.
  while (len > 0 && load_uint(p + 4 * (len - 1), 4, t.big_endian) == 0) --len;
  for (std::size_t k = 0; k < len; ++k) {
    const auto cp = static_cast<std::uint32_t>(load_uint(p + 4 * k, 4, t.big_endian));
    if (cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) bad(name, "invalid unicode code point");
    append_utf8(out, cp);
  }
  return out;
}

// C-order linear index → offset in Fortran-order storage.
std::vector<std::int64_t> fortran_offsets(const std::vector<std::int64_t>& shape, std::int64_t count) {
  const std::size_t nd = shape.size();
  std::vector<std::int64_t> stride(nd, 1);  // Fortran strides: first axis fastest
  for (std::size_t a = 1; a < nd; ++a) stride[a] = stride[a - 1] * shape[a - 1];
  std::vector<std::int64_t> offsets(static_cast<std::size_t>(count));
  std::vector<std::int64_t> idx(nd, 0);
  for (std::int64_t lin = 0; lin < count; ++lin) {
    std::int64_t off = 0;
    for (std::size_t a = 0; a < nd; ++a) off += idx[a] * stride[a];
    offsets[static_cast<std::size_t>(lin)] = off;
    // Advance the C-order multi-index (last axis fastest).
    for (std::size_t a = nd; a-- > 0;) {
      if (++idx[a] < shape[a]) break;
      idx[a] = 0;
    }
  }
  return offsets;
}

// ---- writing ----

std::string shape_text(const std::vector<std::int64_t>& shape) {
  std::string s = "(";
  for (std::size_t a = 0; a < shape.size(); ++a) {
    if (a) s += ", ";
    s += std::to_string(shape[a]);
  }
  if (shape.size() == 1) s += ",";
  return s + ")";
}

std::string npy_preamble(const std::string& descr, const std::vector<std::int64_t>& shape) {
  std::string dict = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + shape_text(shape) + ", }";
  // Pad with spaces and end with '\n' so the data starts on a 64-byte boundary (as numpy does).
  std::size_t prefix = kMagicSize + 2 + 2;  // version 1.0: 2-byte header length
  bool v2 = false;
  std::size_t total = prefix + dict.size() + 1;
  std::size_t padded = (total + 63) / 64 * 64;
  if (padded - prefix > 65535) {
    v2 = true;
    prefix = kMagicSize + 2 + 4;
    total = prefix + dict.size() + 1;
    padded = (total + 63) / 64 * 64;
  }
  dict.append(padded - total, ' ');
  dict += '\n';
  std::string out(kMagic, kMagicSize);
  out += static_cast<char>(v2 ? 2 : 1);
  out += '\0';
  const std::size_t len = dict.size();
  out += static_cast<char>(len & 0xFF);
  out += static_cast<char>((len >> 8) & 0xFF);
  if (v2) {
    out += static_cast<char>((len >> 16) & 0xFF);
    out += static_cast<char>((len >> 24) & 0xFF);
  }
  return out + dict;
}

void check_shape(std::size_t count, const std::vector<std::int64_t>& shape) {
  std::int64_t n = 1;
  for (std::int64_t d : shape) {
    if (d < 0) throw Error(ErrorKind::InvalidArgument, "npy shape has a negative dimension", "shape");
    n *= d;
  }
  if (static_cast<std::size_t>(n) != count)
    throw Error(ErrorKind::InvalidArgument,
                "npy shape " + shape_text(shape) + " does not match " + std::to_string(count) + " values", "shape");
}

void put_le(std::string& out, std::uint64_t bits, std::size_t n) {
  for (std::size_t k = 0; k < n; ++k) out += static_cast<char>((bits >> (8 * k)) & 0xFF);
}

// UTF-8 → code points; throws on malformed input (it becomes a fixed-width UTF-32 numpy string).
std::vector<std::uint32_t> utf8_code_points(const std::string& s) {
  std::vector<std::uint32_t> cps;
  std::size_t i = 0;
  std::uint32_t cp = 0;
  while (i < s.size()) {
    if (!next_code_point(s, i, cp)) throw Error(ErrorKind::InvalidArgument, "text is not valid UTF-8", "text");
    cps.push_back(cp);
  }
  return cps;
}

// ---- zip helpers ----

struct ZipCloser {
  void operator()(zip_t* z) const { zip_discard(z); }
};
struct ZipFileCloser {
  void operator()(zip_file_t* f) const { zip_fclose(f); }
};

}  // namespace

namespace {

// Bytes up to the end of the header (magic, version, header length, header), from the first 12
// bytes of a document (fewer when it is shorter).
std::size_t preamble_size(const std::string& bytes, const std::string& name) {
  if (bytes.size() < kMagicSize + 4 || bytes.compare(0, kMagicSize, kMagic, kMagicSize) != 0)
    bad(name, "not a .npy document (bad magic or truncated)");
  const auto* u = reinterpret_cast<const unsigned char*>(bytes.data());
  const int major = u[6];
  std::size_t header_len = 0, pos = 0;
  if (major == 1) {
    header_len = load_uint(u + 8, 2, false);
    pos = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) bad(name, "truncated .npy header");
    header_len = load_uint(u + 8, 4, false);
    pos = 12;
  } else {
    bad(name, "unsupported .npy version " + std::to_string(major));
  }
  if (header_len > kMaxHeaderSize) bad(name, "truncated .npy header");
  return pos + header_len;
}

// What a .npy header declares, checked against a bound on the number of values.
struct Preamble {
  Header header;
  DType type;
  std::int64_t count = 0;        // values
  std::size_t data_offset = 0;   // where the data starts
  std::uint64_t data_bytes = 0;  // count × item size (0 for a pickle, whose size is not declared)
};

Preamble parse_preamble(const std::string& bytes, const std::string& name, std::int64_t max_values) {
  Preamble p;
  p.data_offset = preamble_size(bytes, name);
  if (p.data_offset > bytes.size()) bad(name, "truncated .npy header");
  const std::size_t header_pos = bytes[6] == 1 ? 10 : 12;
  // Version 3 headers are UTF-8; the keys and dtypes we accept are ASCII either way.
  p.header = HeaderParser(bytes.substr(header_pos, p.data_offset - header_pos), name).parse();
  p.type = parse_dtype(p.header.descr, name);
  const auto too_many = [&] {
    bad(name, "shape " + shape_text(p.header.shape) + " holds more than " + std::to_string(max_values) +
                  " values, the most Caliper reads in one array (docs/model-format.md \"Limits\")");
  };
  p.count = 1;
  for (std::int64_t d : p.header.shape) {
    if (d != 0 && p.count > max_values / d) too_many();
    p.count *= d;
  }
  if (p.count > max_values) too_many();
  p.data_bytes = static_cast<std::uint64_t>(p.count) * p.type.item_size;
  return p;
}

Array parse_npy_within(const std::string& bytes, const std::string& name, std::int64_t max_values) {
  const Preamble pre = parse_preamble(bytes, name, max_values);
  const Header& h = pre.header;
  const DType& t = pre.type;
  const std::int64_t count = pre.count;
  Array a;
  a.dtype = h.descr;
  a.shape = h.shape;
  if (t.kind == Kind::Object) {
    a.is_object = true;  // a pickle: never executed, contents left unread
    return a;
  }
  const std::uint64_t data_bytes = pre.data_bytes;
  const std::uint64_t present = bytes.size() - pre.data_offset;
  if (present < data_bytes)
    bad(name, "truncated: shape " + shape_text(h.shape) + " of " + h.descr + " needs " + std::to_string(data_bytes) +
                  " bytes, " + std::to_string(present) + " present");
  if (present > data_bytes)
    bad(name, std::to_string(present - data_bytes) + " unexpected bytes after the data");

  const unsigned char* data = reinterpret_cast<const unsigned char*>(bytes.data()) + pre.data_offset;
  std::vector<std::int64_t> offsets;
  if (h.fortran_order && h.shape.size() > 1) offsets = fortran_offsets(h.shape, count);
  const auto element = [&](std::int64_t lin) {
    const std::int64_t off = offsets.empty() ? lin : offsets[static_cast<std::size_t>(lin)];
    return data + static_cast<std::size_t>(off) * t.item_size;
  };
  if (t.kind == Kind::Unicode || t.kind == Kind::Bytes) {
    a.strings.reserve(static_cast<std::size_t>(count));
    for (std::int64_t k = 0; k < count; ++k) {
      const unsigned char* p = element(k);
      if (t.kind == Kind::Unicode) {
        a.strings.push_back(decode_unicode(p, t, name));
      } else {
        std::size_t len = t.item_size;
        while (len > 0 && p[len - 1] == 0) --len;
        a.strings.emplace_back(reinterpret_cast<const char*>(p), len);
        // Names and labels go on into JSON and exports, which hold UTF-8 only.
        if (const auto at = invalid_utf8_offset(a.strings.back()); at != std::string_view::npos)
          bad(name, "byte string " + std::to_string(k) + " is not valid UTF-8 (byte " + std::to_string(at) + ")");
      }
    }
  } else {
    a.numbers.resize(static_cast<std::size_t>(count));
    for (std::int64_t k = 0; k < count; ++k) a.numbers[static_cast<std::size_t>(k)] = decode_number(element(k), t);
  }
  return a;
}

}  // namespace

Array parse_npy(const std::string& bytes, const std::string& name) {
  return parse_npy_within(bytes, name, ReadLimits{}.array_values);
}

std::string write_npy_f64(const std::vector<double>& values, const std::vector<std::int64_t>& shape) {
  check_shape(values.size(), shape);
  std::string out = npy_preamble("<f8", shape);
  out.reserve(out.size() + 8 * values.size());
  for (double v : values) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, 8);
    put_le(out, bits, 8);
  }
  return out;
}

std::string write_npy_i64(const std::vector<std::int64_t>& values, const std::vector<std::int64_t>& shape) {
  check_shape(values.size(), shape);
  std::string out = npy_preamble("<i8", shape);
  out.reserve(out.size() + 8 * values.size());
  for (std::int64_t v : values) put_le(out, static_cast<std::uint64_t>(v), 8);
  return out;
}

std::string write_npy_unicode_array(const std::vector<std::string>& utf8_texts, const std::vector<std::int64_t>& shape) {
  check_shape(utf8_texts.size(), shape);
  std::vector<std::vector<std::uint32_t>> cps;
  std::size_t width = 1;  // numpy uses '<U1' even for empty strings
  for (const auto& s : utf8_texts) {
    cps.push_back(utf8_code_points(s));
    width = std::max(width, cps.back().size());
  }
  std::string out = npy_preamble("<U" + std::to_string(width), shape);
  for (const auto& c : cps) {
    for (std::size_t k = 0; k < width; ++k) put_le(out, k < c.size() ? c[k] : 0, 4);
  }
  return out;
}

std::string write_npy_unicode(const std::string& utf8_text) { return write_npy_unicode_array({utf8_text}, {}); }

namespace {

// What is left of ReadLimits' archive-wide bounds while entries are read.
struct Budget {
  std::uint64_t bytes;
  std::int64_t values;
};

// Inflates `f` into `bytes` until it holds `want` bytes or the entry ends; never beyond
// `declared` (the directory's size), whatever the compressed stream says.
void inflate_into(zip_file_t* f, std::string& bytes, std::uint64_t want, std::uint64_t declared, const std::string& name) {
  std::array<char, 1 << 16> chunk;
  while (bytes.size() < want) {
    const zip_int64_t got = zip_fread(f, chunk.data(), chunk.size());
    if (got < 0) bad(name, std::string("corrupt or truncated zip entry: ") + zip_file_strerror(f));
    if (got == 0) return;
    bytes.append(chunk.data(), static_cast<std::size_t>(got));
    if (bytes.size() > declared) bad(name, "zip entry is longer than its directory says");
  }
}

// One entry: its directory size against the limits, then its .npy header against the limits
// and that size, and only then its data.
Array read_entry(zip_t* z, const zip_stat_t& st, const std::string& name, const ReadLimits& limits, Budget& budget) {
  const auto refuse_over = [&](const std::string& what, std::uint64_t most, const char* unit) {
    bad(name, what + " more than " + std::to_string(most) + unit + ", the most Caliper reads (docs/model-format.md \"Limits\")");
  };
  if (st.size > limits.entry_bytes)
    refuse_over("its " + std::to_string(st.size) + " uncompressed bytes are", limits.entry_bytes, " bytes in one entry");
  if (st.size > budget.bytes) refuse_over("with it the archive's entries hold", limits.archive_bytes, " uncompressed bytes");
  budget.bytes -= st.size;
  std::unique_ptr<zip_file_t, ZipFileCloser> f(zip_fopen_index(z, st.index, 0));
  if (!f) bad(name, std::string("cannot read zip entry: ") + zip_strerror(z));
  std::string bytes;
  inflate_into(f.get(), bytes, 12, st.size, name);
  inflate_into(f.get(), bytes, preamble_size(bytes, name), st.size, name);
  const Preamble p = parse_preamble(bytes, name, limits.array_values);
  if (p.type.kind == Kind::Object) return parse_npy_within(bytes.substr(0, p.data_offset), name, limits.array_values);  // left unread
  if (p.count > budget.values)
    refuse_over("with its " + std::to_string(p.count) + " values the archive's arrays hold",
                static_cast<std::uint64_t>(limits.archive_values), " values");
  budget.values -= p.count;
  if (p.data_offset + p.data_bytes != st.size)
    bad(name, "its header declares shape " + shape_text(p.header.shape) + " of " + p.header.descr + " (" +
                  std::to_string(p.data_offset + p.data_bytes) + " bytes) but the zip directory says " +
                  std::to_string(st.size) + " bytes");
  bytes.reserve(static_cast<std::size_t>(st.size));
  inflate_into(f.get(), bytes, st.size + 1, st.size, name);
  if (bytes.size() != st.size)
    bad(name, "truncated zip entry: " + std::to_string(bytes.size()) + " of " + std::to_string(st.size) + " bytes");
  return parse_npy_within(bytes, name, limits.array_values);
}

}  // namespace

namespace {
// The reader itself; read_npz below is its gate.
std::map<std::string, Array> read_archive(const std::string& path, const ReadLimits& limits) {
  int err = 0;
  std::unique_ptr<zip_t, ZipCloser> z(zip_open(path.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &err));
  if (!z) {
    if (err == ZIP_ER_OPEN || err == ZIP_ER_NOENT || err == ZIP_ER_READ || err == ZIP_ER_MEMORY)
      throw Error(ErrorKind::Io, "cannot open '" + path + "'", path);
    zip_error_t ze;
    zip_error_init_with_code(&ze, err);
    const std::string why = zip_error_strerror(&ze);
    zip_error_fini(&ze);
    throw Error(ErrorKind::Format, "'" + path + "' is not a valid .npz (zip) archive: " + why, path);
  }
  std::map<std::string, Array> arrays;
  const zip_int64_t entries = zip_get_num_entries(z.get(), 0);
  if (entries > limits.entries)
    throw Error(ErrorKind::Format, "'" + path + "' has " + std::to_string(entries) + " entries; Caliper reads at most " +
                                       std::to_string(limits.entries) + " (docs/model-format.md \"Limits\")", path);
  Budget budget{limits.archive_bytes, limits.archive_values};
  for (zip_int64_t e = 0; e < entries; ++e) {
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_stat_index(z.get(), static_cast<zip_uint64_t>(e), 0, &st) != 0 || !(st.valid & ZIP_STAT_NAME) ||
        !(st.valid & ZIP_STAT_SIZE))
      throw Error(ErrorKind::Format, "'" + path + "': unreadable zip entry " + std::to_string(e), path);
    st.index = static_cast<zip_uint64_t>(e);
    std::string name = st.name;
    if (!name.empty() && name.back() == '/') continue;  // a directory entry
    if (name.size() > 4 && name.compare(name.size() - 4, 4, ".npy") == 0) name.resize(name.size() - 4);
    arrays[name] = read_entry(z.get(), st, name, limits, budget);
  }
  return arrays;
}
}  // namespace

std::map<std::string, Array> read_npz(const std::string& path, const ReadLimits& limits) {
  return gate("'" + path + "'", "npz", [&] { return read_archive(path, limits); });
}

void write_npz(const std::string& path, const std::map<std::string, std::string>& npy_entries) {
  // libzip writes no file at all for an archive without entries: refuse instead of "succeeding".
  if (npy_entries.empty()) throw Error(ErrorKind::InvalidArgument, "cannot write '" + path + "': an .npz needs at least one array", path);
  int err = 0;
  std::unique_ptr<zip_t, ZipCloser> z(zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err));
  if (!z) throw Error(ErrorKind::Io, "cannot create '" + path + "'", path);
  const auto fail = [&](const std::string& what) {
    throw Error(ErrorKind::Io, "cannot write '" + path + "': " + what + ": " + zip_strerror(z.get()), path);
  };
  // std::map iterates in name order, which fixes the entry order.
  for (const auto& [name, bytes] : npy_entries) {
    zip_source_t* src = zip_source_buffer(z.get(), bytes.data(), bytes.size(), 0);
    if (!src) fail(name);
    const zip_int64_t idx = zip_file_add(z.get(), (name + ".npy").c_str(), src, ZIP_FL_ENC_UTF_8);
    if (idx < 0) {
      zip_source_free(src);
      fail(name);
    }
    const auto i = static_cast<zip_uint64_t>(idx);
    // 1980-01-01 00:00 in DOS time: the same bytes for the same arrays, whenever written.
    if (zip_set_file_compression(z.get(), i, ZIP_CM_DEFLATE, 6) != 0 || zip_file_set_dostime(z.get(), i, 0, 0x21, 0) != 0 ||
        zip_file_set_external_attributes(z.get(), i, 0, ZIP_OPSYS_UNIX, 0100644u << 16) != 0)
      fail(name);
  }
  // zip_close writes to a temporary file and renames it, and reads the buffers until then.
  if (zip_close(z.get()) != 0) fail("close");
  z.release();
}

}  // namespace caliper::npz
