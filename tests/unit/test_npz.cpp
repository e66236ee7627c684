// .npy / .npz reading and writing: hand-built documents with known contents, every supported
// dtype and header version, truncation at every byte, and reproducible archives.
#include <gtest/gtest.h>
#include <zip.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <limits>

#include "caliper/errors.h"
#include "fixtures.h"
#include "temp_files.h"
#include "caliper/io/npz.h"

using namespace caliper;
using test::TempDir;
using test::kind_of;
using test::read_file;
using test::write_file;
namespace fs = std::filesystem;

namespace {

// A .npy document built by hand (independently of the library's writer).
std::string npy(const std::string& descr, const std::string& shape, const std::string& data, bool fortran = false,
                int version = 1) {
  std::string dict = "{'descr': '" + descr + "', 'fortran_order': " + (fortran ? "True" : "False") + ", 'shape': " + shape + ", }\n";
  std::string out = "\x93NUMPY";
  out += static_cast<char>(version);
  out += '\0';
  const std::size_t len = dict.size();
  out += static_cast<char>(len & 0xFF);
  out += static_cast<char>(len >> 8);
  if (version >= 2) out += std::string(2, '\0');
  return out + dict + data;
}

template <typename T>
std::string le_bytes(std::initializer_list<T> values) {
  std::string out;
  for (T v : values) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));  // this machine is little-endian (x86-64)
    out.append(b, sizeof(T));
  }
  return out;
}

template <typename T>
std::string be_bytes(std::initializer_list<T> values) {
  std::string out;
  for (T v : values) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    for (std::size_t k = sizeof(T); k-- > 0;) out += b[k];
  }
  return out;
}

std::string utf32le(const std::u32string& s, std::size_t width) {
  std::string out;
  for (std::size_t k = 0; k < width; ++k) {
    const std::uint32_t c = k < s.size() ? static_cast<std::uint32_t>(s[k]) : 0;
    for (int b = 0; b < 4; ++b) out += static_cast<char>((c >> (8 * b)) & 0xFF);
  }
  return out;
}




// A zip source of `size` bytes, `head` followed by zeros, produced as libzip reads it: archives
// that inflate to hundreds of megabytes without the test ever holding them.
struct ZeroSource {
  std::string head;
  std::uint64_t size = 0;
  std::uint64_t pos = 0;
  zip_error_t error;
};

zip_int64_t zero_source(void* state, void* data, zip_uint64_t len, zip_source_cmd_t cmd) {
  auto* s = static_cast<ZeroSource*>(state);
  switch (cmd) {
    case ZIP_SOURCE_OPEN: s->pos = 0; return 0;
    case ZIP_SOURCE_READ: {
      const std::uint64_t n = std::min<std::uint64_t>(len, s->size - s->pos);
      auto* out = static_cast<char*>(data);
      std::memset(out, 0, static_cast<std::size_t>(n));
      for (std::uint64_t k = 0; k < n && s->pos + k < s->head.size(); ++k) out[k] = s->head[static_cast<std::size_t>(s->pos + k)];
      s->pos += n;
      return static_cast<zip_int64_t>(n);
    }
    case ZIP_SOURCE_CLOSE:
    case ZIP_SOURCE_FREE: return 0;
    case ZIP_SOURCE_STAT: {
      auto* st = static_cast<zip_stat_t*>(data);
      zip_stat_init(st);
      st->size = s->size;
      st->valid |= ZIP_STAT_SIZE;
      return sizeof(zip_stat_t);
    }
    case ZIP_SOURCE_ERROR: return zip_error_to_data(&s->error, data, len);
    case ZIP_SOURCE_SUPPORTS:
      return zip_source_make_command_bitmap(ZIP_SOURCE_OPEN, ZIP_SOURCE_READ, ZIP_SOURCE_CLOSE, ZIP_SOURCE_STAT,
                                            ZIP_SOURCE_ERROR, ZIP_SOURCE_FREE, -1);
    default: return -1;
  }
}

// A deflated .npz whose entries are `head` followed by zeros up to `size` bytes.
void write_zero_npz(const std::string& path, std::vector<ZeroSource>& entries, const std::vector<std::string>& names) {
  int err = 0;
  zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
  ASSERT_NE(z, nullptr);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    zip_error_init(&entries[k].error);
    zip_source_t* src = zip_source_function(z, zero_source, &entries[k]);
    ASSERT_NE(src, nullptr);
    const zip_int64_t idx = zip_file_add(z, (names[k] + ".npy").c_str(), src, 0);
    ASSERT_GE(idx, 0);
    ASSERT_EQ(zip_set_file_compression(z, static_cast<zip_uint64_t>(idx), ZIP_CM_DEFLATE, 1), 0);
  }
  ASSERT_EQ(zip_close(z), 0) << zip_strerror(z);
}

// The .npy header alone (no data) for a C-order array.
std::string npy_head(const std::string& descr, const std::string& shape) { return npy(descr, shape, ""); }

Error npz_error(const std::string& path, const npz::ReadLimits& limits = {}) {
  try {
    npz::read_npz(path, limits);
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "reading " << path << " did not throw";
  return Error(ErrorKind::Unsupported, "none");
}
}  // namespace

TEST(Npy, ParsesFloat64InCOrder) {
  const auto a = npz::parse_npy(npy("<f8", "(2, 3)", le_bytes<double>({1, 2, 3, 4, 5, -6.5})), "x");
  EXPECT_EQ(a.dtype, "<f8");
  EXPECT_EQ(a.shape, (std::vector<std::int64_t>{2, 3}));
  EXPECT_EQ(a.size(), 6);
  EXPECT_EQ(a.numbers, (std::vector<double>{1, 2, 3, 4, 5, -6.5}));
  EXPECT_FALSE(a.is_object);
}

TEST(Npy, ConvertsEveryNumericDtype) {
  EXPECT_EQ(npz::parse_npy(npy("<f4", "(2,)", le_bytes<float>({0.5f, -2.25f})), "x").numbers, (std::vector<double>{0.5, -2.25}));
  EXPECT_EQ(npz::parse_npy(npy(">f4", "(2,)", be_bytes<float>({0.5f, -2.25f})), "x").numbers, (std::vector<double>{0.5, -2.25}));
  EXPECT_EQ(npz::parse_npy(npy(">f8", "(1,)", be_bytes<double>({1e300})), "x").numbers, (std::vector<double>{1e300}));
  EXPECT_EQ(npz::parse_npy(npy("|i1", "(2,)", le_bytes<std::int8_t>({-128, 127})), "x").numbers, (std::vector<double>{-128, 127}));
  EXPECT_EQ(npz::parse_npy(npy("<i2", "(2,)", le_bytes<std::int16_t>({-32768, 7})), "x").numbers, (std::vector<double>{-32768, 7}));
  EXPECT_EQ(npz::parse_npy(npy("<i4", "(2,)", le_bytes<std::int32_t>({-1, 2000000000})), "x").numbers,
            (std::vector<double>{-1, 2000000000}));
  EXPECT_EQ(npz::parse_npy(npy("<i8", "(2,)", le_bytes<std::int64_t>({-1, std::int64_t{1} << 40})), "x").numbers,
            (std::vector<double>{-1, 1099511627776.0}));
  EXPECT_EQ(npz::parse_npy(npy(">i8", "(1,)", be_bytes<std::int64_t>({-3})), "x").numbers, (std::vector<double>{-3}));
  EXPECT_EQ(npz::parse_npy(npy("|u1", "(2,)", le_bytes<std::uint8_t>({0, 255})), "x").numbers, (std::vector<double>{0, 255}));
  EXPECT_EQ(npz::parse_npy(npy("<u2", "(1,)", le_bytes<std::uint16_t>({65535})), "x").numbers, (std::vector<double>{65535}));
  EXPECT_EQ(npz::parse_npy(npy("<u4", "(1,)", le_bytes<std::uint32_t>({4294967295u})), "x").numbers,
            (std::vector<double>{4294967295.0}));
  EXPECT_EQ(npz::parse_npy(npy("<u8", "(1,)", le_bytes<std::uint64_t>({5})), "x").numbers, (std::vector<double>{5}));
  EXPECT_EQ(npz::parse_npy(npy("|b1", "(3,)", std::string("\x01\x00\x01", 3)), "x").numbers, (std::vector<double>{1, 0, 1}));
}

TEST(Npy, ReadsUnicodeAndBytes) {
  const auto a = npz::parse_npy(npy("<U5", "(2,)", utf32le(U"hip", 5) + utf32le(U"h\u00e9\U0001F600", 5)), "names");
  EXPECT_EQ(a.strings, (std::vector<std::string>{"hip", "h\xc3\xa9\xf0\x9f\x98\x80"}));
  EXPECT_TRUE(a.numbers.empty());
  std::string be;
  for (char32_t c : std::u32string(U"ab")) be += std::string("\0\0\0", 3) + static_cast<char>(c);
  EXPECT_EQ(npz::parse_npy(npy(">U2", "()", be), "x").strings, (std::vector<std::string>{"ab"}));
  EXPECT_EQ(npz::parse_npy(npy("|S4", "(1,)", std::string("csc\0", 4)), "x").strings, (std::vector<std::string>{"csc"}));
  EXPECT_EQ(kind_of([] { npz::parse_npy(npy("<U1", "()", le_bytes<std::uint32_t>({0x110000})), "x"); }), ErrorKind::Format);
  // Byte strings go on into JSON and exports: one that is not UTF-8 is refused, naming it (the
  // fuzzer found '\xc1\xb6...' read as is, 2026-11-29).
  try {
    npz::parse_npy(npy("|S4", "(2,)", std::string("ok\0\0\xc1\xb6" "ab", 8)), "labels");
    ADD_FAILURE() << "invalid UTF-8 accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Format);
    EXPECT_NE(std::string(e.what()).find("labels"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("byte string 1 is not valid UTF-8"), std::string::npos) << e.what();
  }
  EXPECT_EQ(npz::parse_npy(npy("|S4", "(1,)", std::string("h\xc3\xa9\0", 4)), "x").strings, (std::vector<std::string>{"h\xc3\xa9"}));
}

TEST(Npy, ConvertsFortranOrderToCOrder) {
  // 2×3 matrix [[1,2,3],[4,5,6]] stored column by column.
  const auto a = npz::parse_npy(npy("<f8", "(2, 3)", le_bytes<double>({1, 4, 2, 5, 3, 6}), true), "x");
  EXPECT_EQ(a.numbers, (std::vector<double>{1, 2, 3, 4, 5, 6}));
  // 2×2×2: element (i,j,k) = 100i + 10j + k, Fortran storage has i fastest.
  std::vector<double> f;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) f.push_back(100 * i + 10 * j + k);
  std::string raw(reinterpret_cast<const char*>(f.data()), f.size() * 8);
  const auto b = npz::parse_npy(npy("<f8", "(2, 2, 2)", raw, true), "x");
  EXPECT_EQ(b.numbers, (std::vector<double>{0, 1, 10, 11, 100, 101, 110, 111}));
}

TEST(Npy, AcceptsHeaderVersionsAndOldShapes) {
  const std::string data = le_bytes<double>({7, 8});
  for (int v : {1, 2, 3}) EXPECT_EQ(npz::parse_npy(npy("<f8", "(2,)", data, false, v), "x").numbers, (std::vector<double>{7, 8}));
  EXPECT_EQ(npz::parse_npy(npy("<f8", "(1L, 2L)", data), "x").shape, (std::vector<std::int64_t>{1, 2}));
  const auto scalar = npz::parse_npy(npy("<i8", "()", le_bytes<std::int64_t>({42})), "x");
  EXPECT_TRUE(scalar.shape.empty());
  EXPECT_EQ(scalar.size(), 1);
  EXPECT_EQ(scalar.numbers, (std::vector<double>{42}));
  const auto empty = npz::parse_npy(npy("<f8", "(0, 3)", ""), "x");
  EXPECT_EQ(empty.size(), 0);
  EXPECT_TRUE(empty.numbers.empty());
}

TEST(Npy, ObjectArraysAreListedButNeverUnpickled) {
  const auto a = npz::parse_npy(npy("|O", "()", std::string("\x80\x02}q\x00(U\x05pelvisq\x01K\x00u.", 20)), "joint2num");
  EXPECT_TRUE(a.is_object);
  EXPECT_TRUE(a.numbers.empty());
  EXPECT_TRUE(a.strings.empty());
}

TEST(Npy, RejectsMalformedDocuments) {
  const auto format_error = [](const std::string& bytes) {
    return kind_of([&] { npz::parse_npy(bytes, "arr"); }) == ErrorKind::Format;
  };
  EXPECT_TRUE(format_error("PK\x03\x04 not npy"));
  EXPECT_TRUE(format_error(""));
  EXPECT_TRUE(format_error(npy("<f8", "(2,)", le_bytes<double>({1, 2}), false, 9)));  // unknown version
  EXPECT_TRUE(format_error(npy("<c16", "(1,)", std::string(16, '\0'))));             // complex
  EXPECT_TRUE(format_error(npy("<f2", "(1,)", std::string(2, '\0'))));               // half
  EXPECT_TRUE(format_error(npy("<f8", "(2,)", le_bytes<double>({1, 2, 3}))));       // trailing bytes
  EXPECT_TRUE(format_error(npy("<f8", "(2 3)", le_bytes<double>({1, 2}))));
  EXPECT_TRUE(format_error("\x93NUMPY\x01\x00\xff\xff{'descr': '<f8'"));  // header length past the end
  // A structured dtype (list descr).
  std::string s = npy("<f8", "(1,)", le_bytes<double>({1}));
  s.replace(s.find("'<f8'"), 5, "[('a', '<f8')]");
  EXPECT_TRUE(format_error(s));
  // Absurd shapes are rejected before anything is allocated.
  EXPECT_TRUE(format_error(npy("<f8", "(1000000000000,)", le_bytes<double>({1}))));
  EXPECT_TRUE(format_error(npy("<f8", "(4294967296, 4294967296)", "")));
}

TEST(Npy, TruncationAtEveryByteIsAFormatErrorNamingTheArray) {
  const std::string whole = npy("<f4", "(3, 2)", le_bytes<float>({1, 2, 3, 4, 5, 6}));
  for (std::size_t cut = 0; cut < whole.size(); ++cut) {
    try {
      npz::parse_npy(whole.substr(0, cut), "v_template");
      ADD_FAILURE() << "no error at cut " << cut;
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::Format) << cut;
      EXPECT_EQ(e.field(), "v_template") << cut;
    }
  }
}

TEST(NpyWriter, WritesNumpyHeadersAlignedTo64Bytes) {
  const std::string bytes = npz::write_npy_f64({1, 2, 3, 4, 5, 6}, {2, 3});
  ASSERT_GT(bytes.size(), 10u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const std::size_t header_len = static_cast<unsigned char>(bytes[8]) | (static_cast<unsigned char>(bytes[9]) << 8);
  EXPECT_EQ((10 + header_len) % 64, 0u);
  EXPECT_EQ(bytes.size(), 10 + header_len + 48);
  const std::string header = bytes.substr(10, header_len);
  EXPECT_EQ(header.rfind("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }", 0), 0u);
  EXPECT_EQ(header.back(), '\n');
  EXPECT_NE(npz::write_npy_i64({5}, {1}).find("'shape': (1,)"), std::string::npos);
  EXPECT_NE(npz::write_npy_i64({5}, {}).find("'shape': ()"), std::string::npos);
  EXPECT_EQ(kind_of([] { npz::write_npy_f64({1, 2, 3}, {2, 2}); }), ErrorKind::InvalidArgument);
}

TEST(NpyWriter, RoundTripsBitForBit) {
  const std::vector<double> values = {0.1, -0.0, 5e-324, std::numeric_limits<double>::max(),
                                      std::numeric_limits<double>::quiet_NaN(), -std::numeric_limits<double>::infinity()};
  const auto a = npz::parse_npy(npz::write_npy_f64(values, {2, 3}), "x");
  ASSERT_EQ(a.numbers.size(), values.size());
  EXPECT_EQ(std::memcmp(a.numbers.data(), values.data(), values.size() * sizeof(double)), 0);
  const auto i = npz::parse_npy(npz::write_npy_i64({-1, 0, std::int64_t{1} << 52}, {3}), "x");
  EXPECT_EQ(i.dtype, "<i8");
  EXPECT_EQ(i.numbers, (std::vector<double>{-1, 0, 4503599627370496.0}));
  const std::string text = "caliper \xc3\xa9t\xc3\xa9 \xf0\x9f\x93\x8f";
  const auto u = npz::parse_npy(npz::write_npy_unicode(text), "x");
  EXPECT_EQ(u.dtype, "<U13");  // 13 code points
  EXPECT_TRUE(u.shape.empty());
  EXPECT_EQ(u.strings, (std::vector<std::string>{text}));
  const auto arr = npz::parse_npy(npz::write_npy_unicode_array({"pelvis", "", "left_hip"}, {3}), "x");
  EXPECT_EQ(arr.strings, (std::vector<std::string>{"pelvis", "", "left_hip"}));
  EXPECT_EQ(npz::parse_npy(npz::write_npy_unicode(""), "x").strings, (std::vector<std::string>{""}));
  EXPECT_EQ(kind_of([] { npz::write_npy_unicode("bad \xff utf8"); }), ErrorKind::InvalidArgument);
  EXPECT_EQ(kind_of([] { npz::write_npy_unicode("cut \xc3"); }), ErrorKind::InvalidArgument);
}

TEST(Npz, RoundTripsAndIsReproducible) {
  TempDir dir;
  std::map<std::string, std::string> entries = {{"b", npz::write_npy_f64({1.5, 2.5}, {2})},
                                                {"a", npz::write_npy_unicode("hello")},
                                                {"c", npz::write_npy_i64({3}, {})}};
  npz::write_npz(dir / "one.npz", entries);
  npz::write_npz(dir / "two.npz", entries);
  EXPECT_EQ(read_file(dir / "one.npz"), read_file(dir / "two.npz"));

  const auto arrays = npz::read_npz(dir / "one.npz");
  ASSERT_EQ(arrays.size(), 3u);
  EXPECT_EQ(arrays.at("a").strings, (std::vector<std::string>{"hello"}));
  EXPECT_EQ(arrays.at("b").numbers, (std::vector<double>{1.5, 2.5}));
  EXPECT_EQ(arrays.at("c").numbers, (std::vector<double>{3}));

  // Entries are named <array>.npy, deflated, in name order.
  int err = 0;
  zip_t* z = zip_open((dir / "one.npz").c_str(), ZIP_RDONLY, &err);
  ASSERT_NE(z, nullptr);
  ASSERT_EQ(zip_get_num_entries(z, 0), 3);
  const char* expected[] = {"a.npy", "b.npy", "c.npy"};
  for (zip_uint64_t i = 0; i < 3; ++i) {
    zip_stat_t st;
    ASSERT_EQ(zip_stat_index(z, i, 0, &st), 0);
    EXPECT_STREQ(st.name, expected[i]);
    EXPECT_EQ(st.comp_method, ZIP_CM_DEFLATE);
  }
  zip_discard(z);
}

TEST(Npz, ReadsStoredEntries) {
  TempDir dir;
  const std::string bytes = npz::write_npy_f64({4, 5, 6}, {3});
  int err = 0;
  zip_t* z = zip_open((dir / "stored.npz").c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
  ASSERT_NE(z, nullptr);
  zip_source_t* src = zip_source_buffer(z, bytes.data(), bytes.size(), 0);
  const zip_int64_t idx = zip_file_add(z, "weights.npy", src, 0);
  ASSERT_GE(idx, 0);
  ASSERT_EQ(zip_set_file_compression(z, static_cast<zip_uint64_t>(idx), ZIP_CM_STORE, 0), 0);
  ASSERT_EQ(zip_close(z), 0);
  const auto arrays = npz::read_npz(dir / "stored.npz");
  EXPECT_EQ(arrays.at("weights").numbers, (std::vector<double>{4, 5, 6}));
}

TEST(Npz, BadArchivesGiveClearErrors) {
  TempDir dir;
  EXPECT_EQ(kind_of([&] { npz::read_npz(dir / "absent.npz"); }), ErrorKind::Io);
  write_file(dir / "text.npz", "this is not a zip archive at all, just some text\n");
  EXPECT_EQ(kind_of([&] { npz::read_npz(dir / "text.npz"); }), ErrorKind::Format);
  write_file(dir / "empty.npz", "");
  EXPECT_EQ(kind_of([&] { npz::read_npz(dir / "empty.npz"); }), ErrorKind::Format);

  std::vector<double> many(2000);
  for (std::size_t k = 0; k < many.size(); ++k) many[k] = std::sin(static_cast<double>(k));
  npz::write_npz(dir / "good.npz", {{"v", npz::write_npy_f64(many, {1000, 2})}, {"w", npz::write_npy_i64({1, 2}, {2})}});
  const std::string whole = read_file(dir / "good.npz");
  // Cut anywhere: an error (usually Format), never a crash or a silently short array.
  for (std::size_t cut : {std::size_t{0}, std::size_t{3}, std::size_t{30}, whole.size() / 3, whole.size() / 2,
                          whole.size() - 40, whole.size() - 1}) {
    write_file(dir / "cut.npz", whole.substr(0, cut));
    EXPECT_EQ(kind_of([&] { npz::read_npz(dir / "cut.npz"); }), ErrorKind::Format) << "cut at " << cut;
  }
  // Corrupt the deflated data in the middle of the first entry: the CRC or the inflater catches it.
  std::string corrupt = whole;
  for (std::size_t k = 200; k < 260; ++k) corrupt[k] = static_cast<char>(corrupt[k] ^ 0x5A);
  write_file(dir / "corrupt.npz", corrupt);
  EXPECT_EQ(kind_of([&] { npz::read_npz(dir / "corrupt.npz"); }), ErrorKind::Format);
}

TEST(Npz, AMalformedEntryNamesTheArray) {
  TempDir dir;
  npz::write_npz(dir / "bad.npz", {{"shapedirs", npz::write_npy_f64({1, 2}, {2}).substr(0, 70)}});
  try {
    npz::read_npz(dir / "bad.npz");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Format);
    EXPECT_EQ(e.field(), "shapedirs");
  }
}

// Audit (docs/reliability.md): a 255 KB archive whose one entry, a uint8 array of hundreds of
// millions of zeros, once grew to 2.4 GB (its bytes, then a double per value). The header's
// shape is now checked against ReadLimits before the data is inflated.
TEST(NpzLimits, AZipBombIsRefusedFromItsHeader) {
  TempDir dir;
  const std::int64_t values = 40'000'000;  // 40 MB of zeros, ~40 KB deflated; 320 MB as doubles
  ASSERT_GT(values, npz::ReadLimits{}.array_values);
  const std::string head = npy_head("|u1", "(40000000,)");
  std::vector<ZeroSource> entries(1);
  entries[0].head = head;
  entries[0].size = head.size() + static_cast<std::uint64_t>(values);
  write_zero_npz(dir / "bomb.npz", entries, {"weights"});
  EXPECT_LT(fs::file_size(dir / "bomb.npz"), 200'000u);
  const Error e = npz_error(dir / "bomb.npz");
  EXPECT_EQ(e.kind(), ErrorKind::Format);
  EXPECT_EQ(e.field(), "weights");
  EXPECT_NE(std::string(e.what()).find("the most Caliper reads"), std::string::npos) << e.what();
}

// The header must agree with the zip directory's size: a small declared shape followed by
// megabytes of padding is refused before the padding is inflated.
TEST(NpzLimits, HeaderAndDirectoryMustAgree) {
  TempDir dir;
  std::vector<ZeroSource> entries(1);
  entries[0].head = npy_head("<f8", "(10,)");
  entries[0].size = entries[0].head.size() + 80 + 5'000'000;
  write_zero_npz(dir / "padded.npz", entries, {"v_template"});
  const Error e = npz_error(dir / "padded.npz");
  EXPECT_EQ(e.field(), "v_template");
  EXPECT_NE(std::string(e.what()).find("zip directory"), std::string::npos) << e.what();
}

// Each bound of ReadLimits, with small limits so the files stay tiny.
TEST(NpzLimits, EveryLimitIsEnforcedAndNamesTheArray) {
  TempDir dir;
  const std::vector<double> sixty(60, 1.5);
  npz::write_npz(dir / "two.npz", {{"a", npz::write_npy_f64(sixty, {60})}, {"b", npz::write_npy_f64(sixty, {6, 10})}});
  EXPECT_EQ(npz::read_npz(dir / "two.npz").size(), 2u);
  npz::ReadLimits limits;
  limits.array_values = 59;
  Error e = npz_error(dir / "two.npz", limits);
  EXPECT_EQ(e.field(), "a");
  EXPECT_NE(std::string(e.what()).find("more than 59 values"), std::string::npos) << e.what();
  limits = {};
  limits.archive_values = 100;
  e = npz_error(dir / "two.npz", limits);
  EXPECT_EQ(e.field(), "b");
  EXPECT_NE(std::string(e.what()).find("more than 100"), std::string::npos) << e.what();
  limits = {};
  limits.entry_bytes = 400;  // each entry is 128 header + 480 data bytes
  e = npz_error(dir / "two.npz", limits);
  EXPECT_EQ(e.field(), "a");
  EXPECT_NE(std::string(e.what()).find("uncompressed bytes"), std::string::npos) << e.what();
  limits = {};
  limits.archive_bytes = 1000;
  EXPECT_EQ(npz_error(dir / "two.npz", limits).field(), "b");
  limits = {};
  limits.entries = 1;
  EXPECT_EQ(npz_error(dir / "two.npz", limits).kind(), ErrorKind::Format);
  // At the limits exactly, the archive loads.
  limits = {};
  limits.array_values = 60;
  limits.archive_values = 120;
  EXPECT_EQ(npz::read_npz(dir / "two.npz", limits).size(), 2u);
}

namespace caliper {
// libzip writes no file for an archive without entries; write_npz says so instead of "succeeding"
// (found by fuzz_npz's round trip, fuzz/regressions/npz/).
TEST(Npz, WritingNoArraysIsRefused) {
  test::TempDir dir;
  const std::string path = (dir.path / "empty.npz").string();
  EXPECT_THROW(npz::write_npz(path, {}), Error);
  EXPECT_FALSE(std::filesystem::exists(path));
}
}  // namespace caliper
