// Model files: Caliper's native .npz body-model format (docs/model-format.md) and SMPL / SMPL-X
// .npz files (Loper et al. 2015; arrays as the smplx Python package uses them, SPEC.md).
// Both are untrusted input: every array is checked for presence, dtype, shape, finiteness and
// index ranges, and errors name the array, before a BodyModel (which validates again) is built.
#include "caliper/io/model_files.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <dlfcn.h>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "caliper/errors.h"
#include "gate.h"
#include "caliper/io/npz.h"

#ifndef CALIPER_MODELS_DIR
#define CALIPER_MODELS_DIR "models"
#endif

namespace caliper {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using npz::Array;
using ArrayMap = std::map<std::string, Array>;
using SparseRM = Eigen::SparseMatrix<double, Eigen::RowMajor>;

constexpr const char* kFormatName = "caliper-body-model";
constexpr std::int64_t kFormatVersion = 1;
constexpr int kMaxSmplShapes = 400;  // SMPL-X files carry 300 shape + 100 expression directions

// The arrays of one file, with the file name for error messages.
class Arrays {
 public:
  Arrays(std::string path, ArrayMap arrays) : path_(std::move(path)), arrays_(std::move(arrays)) {}

  [[noreturn]] void fail(const std::string& array, const std::string& what) const {
    throw Error(ErrorKind::Format, "'" + path_ + "': array '" + array + "': " + what, array);
  }
  bool has(const std::string& name) const { return arrays_.count(name) != 0; }
  const std::string& path() const { return path_; }

  const Array& get(const std::string& name) const {
    auto it = arrays_.find(name);
    if (it == arrays_.end()) fail(name, "missing");
    if (it->second.is_object)
      fail(name, "is a pickled Python object (dtype " + it->second.dtype + "); Caliper never unpickles. "
                 "Save it as a plain numeric or unicode array");
    return it->second;
  }

  // A numeric array with the given shape; -1 in `shape` accepts any size along that axis.
  const Array& numeric(const std::string& name, const std::vector<std::int64_t>& shape) const {
    const Array& a = get(name);
    if (a.dtype.size() < 2 || a.dtype[1] == 'U' || a.dtype[1] == 'S')
      fail(name, "expected numbers, found dtype " + a.dtype);
    bool ok = a.shape.size() == shape.size();
    for (std::size_t k = 0; ok && k < shape.size(); ++k) ok = shape[k] < 0 || a.shape[k] == shape[k];
    if (!ok) fail(name, "has shape " + text(a.shape) + ", expected " + text(shape));
    return a;
  }

  const Array& finite(const std::string& name, const std::vector<std::int64_t>& shape) const {
    const Array& a = numeric(name, shape);
    for (std::size_t k = 0; k < a.numbers.size(); ++k)
      if (!std::isfinite(a.numbers[k])) fail(name, "contains NaN or infinity (element " + std::to_string(k) + ")");
    return a;
  }

  // Integer-valued entries in [lo, hi), whatever the stored dtype (SMPL files use floats too).
  std::vector<std::int64_t> indices(const std::string& name, const std::vector<std::int64_t>& shape, std::int64_t lo,
                                    std::int64_t hi) const {
    const Array& a = numeric(name, shape);
    std::vector<std::int64_t> out(a.numbers.size());
    for (std::size_t k = 0; k < a.numbers.size(); ++k) {
      const double v = a.numbers[k];
      if (!std::isfinite(v) || v != std::floor(v) || v < static_cast<double>(lo) || v >= static_cast<double>(hi))
        fail(name, "entry " + std::to_string(k) + " = " + number(v) + " is not an integer in [" + std::to_string(lo) +
                       ", " + std::to_string(hi) + ")");
      out[k] = static_cast<std::int64_t>(v);
    }
    return out;
  }

  // One string: a 0-d (or one-element) unicode or bytes array.
  std::string string(const std::string& name) const {
    const Array& a = get(name);
    if (a.strings.size() != 1 || a.size() != 1) fail(name, "expected a single string, found dtype " + a.dtype + " shape " + text(a.shape));
    return a.strings[0];
  }

  std::vector<std::string> strings(const std::string& name, std::int64_t count) const {
    const Array& a = get(name);
    if (a.shape.size() != 1 || static_cast<std::int64_t>(a.strings.size()) != count || a.shape[0] != count)
      fail(name, "expected " + std::to_string(count) + " strings, found dtype " + a.dtype + " shape " + text(a.shape));
    return a.strings;
  }

  static std::string text(const std::vector<std::int64_t>& shape) {
    std::string s = "(";
    for (std::size_t k = 0; k < shape.size(); ++k) s += (k ? ", " : "") + (shape[k] < 0 ? std::string("any") : std::to_string(shape[k]));
    return s + (shape.size() == 1 ? ",)" : ")");
  }
  static std::string number(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  }

 private:
  std::string path_;
  ArrayMap arrays_;
};

// The optional UV layout: uv_coordinates (U×2, in [0, 1]) and uv_faces (F×3, one row per face).
// Shapes are checked against the face count before anything is copied; U is at most 3F (one UV
// per face corner).
void read_uv_layout(const Arrays& f, BodyModelData& d) {
  const bool has_coordinates = f.has("uv_coordinates"), has_faces = f.has("uv_faces");
  if (!has_coordinates && !has_faces) return;
  if (!has_coordinates) f.fail("uv_coordinates", "missing while 'uv_faces' is present");
  if (!has_faces) f.fail("uv_faces", "missing while 'uv_coordinates' is present");
  const std::int64_t face_count = d.faces.rows();
  const Array& uv_shape = f.numeric("uv_coordinates", {-1, 2});
  const std::int64_t u = uv_shape.shape[0];
  if (u < 1 || u > 3 * face_count)
    f.fail("uv_coordinates", "has " + std::to_string(u) + " rows, expected 1 to 3×" + std::to_string(face_count) + " (faces)");
  f.numeric("uv_faces", {face_count, 3});  // the row count must be the face count
  const Array& uv = f.finite("uv_coordinates", {u, 2});
  for (std::size_t k = 0; k < uv.numbers.size(); ++k)
    if (uv.numbers[k] < 0 || uv.numbers[k] > 1)
      f.fail("uv_coordinates", "entry " + std::to_string(k) + " = " + Arrays::number(uv.numbers[k]) + " is outside [0, 1]");
  const auto uv_faces = f.indices("uv_faces", {face_count, 3}, 0, u);
  d.uv_coordinates = Eigen::Map<const UvCoordinates>(uv.numbers.data(), u, 2);
  d.uv_faces.resize(face_count, 3);
  for (std::size_t k = 0; k < uv_faces.size(); ++k) d.uv_faces.data()[k] = static_cast<std::int32_t>(uv_faces[k]);
}

// ---- sparse matrices as scipy's CSR/CSC parts: <prefix>_data, _indices, _indptr, _shape ----

// A rows × cols matrix (the shape the dense arrays already fixed). The declared shape, the entry
// count and every index are checked before anything is allocated, so a hostile shape (0 columns,
// 2^31 rows) is an Error(Format) naming the array, not a crash or gigabytes of row offsets.
SparseRM read_sparse(const Arrays& f, const std::string& prefix, bool csc, std::int64_t rows, std::int64_t cols) {
  const auto shape = f.indices(prefix + "_shape", {2}, 0, std::int64_t{1} << 31);
  if (shape[0] != rows || shape[1] != cols)
    f.fail(prefix + "_shape", "is (" + std::to_string(shape[0]) + ", " + std::to_string(shape[1]) + "), expected (" +
                                  std::to_string(rows) + ", " + std::to_string(cols) + ")");
  const std::int64_t outer = csc ? cols : rows, inner = csc ? rows : cols;
  const Array& data = f.finite(prefix + "_data", {-1});
  const std::int64_t nnz = data.shape[0];
  if (nnz > rows * cols)
    f.fail(prefix + "_data", "has " + std::to_string(nnz) + " entries, more than a " + std::to_string(rows) + " x " +
                                 std::to_string(cols) + " matrix holds");
  const auto index = f.indices(prefix + "_indices", {nnz}, 0, inner);
  const auto ptr = f.indices(prefix + "_indptr", {outer + 1}, 0, nnz + 1);
  if (ptr.front() != 0 || ptr.back() != nnz) f.fail(prefix + "_indptr", "must start at 0 and end at " + std::to_string(nnz));
  for (std::size_t o = 0; o + 1 < ptr.size(); ++o)
    if (ptr[o + 1] < ptr[o]) f.fail(prefix + "_indptr", "decreases at " + std::to_string(o));
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(nnz));
  for (std::int64_t o = 0; o < outer; ++o) {
    const auto begin = ptr[static_cast<std::size_t>(o)], end = ptr[static_cast<std::size_t>(o) + 1];
    for (std::int64_t k = begin; k < end; ++k) {
      const auto in = index[static_cast<std::size_t>(k)];
      const double v = data.numbers[static_cast<std::size_t>(k)];
      triplets.emplace_back(static_cast<int>(csc ? in : o), static_cast<int>(csc ? o : in), v);
    }
  }
  SparseRM m(rows, cols);
  m.setFromTriplets(triplets.begin(), triplets.end());  // duplicates (legal in scipy) are summed
  m.makeCompressed();
  return m;
}

void write_sparse(std::map<std::string, std::string>& out, const std::string& prefix, SparseRM m) {
  m.makeCompressed();
  const auto nnz = static_cast<std::size_t>(m.nonZeros());
  std::vector<double> data(m.valuePtr(), m.valuePtr() + nnz);
  std::vector<std::int64_t> indices(m.innerIndexPtr(), m.innerIndexPtr() + nnz);
  std::vector<std::int64_t> indptr(m.outerIndexPtr(), m.outerIndexPtr() + m.outerSize() + 1);
  const auto n = static_cast<std::int64_t>(nnz);
  out[prefix + "_data"] = npz::write_npy_f64(data, {n});
  out[prefix + "_indices"] = npz::write_npy_i64(indices, {n});
  out[prefix + "_indptr"] = npz::write_npy_i64(indptr, {static_cast<std::int64_t>(indptr.size())});
  out[prefix + "_shape"] = npz::write_npy_i64({m.rows(), m.cols()}, {2});
}

// ---- measurement definitions as JSON (native `measurements` array and landmarks/smpl.json) ----

json definitions_to_json(const std::vector<MeasurementDefinition>& defs) {
  json list = json::array();
  for (const auto& d : defs)
    list.push_back({{"name", d.name},
                    {"kind", to_string(d.kind)},
                    {"landmarks", d.landmarks},
                    {"plane_normal", to_string(d.plane_normal)},
                    {"description", d.description}});
  return list;
}

std::vector<MeasurementDefinition> definitions_from_json(const json& list, const std::string& where) {
  const auto bad = [&](const std::string& what) {
    throw Error(ErrorKind::Format, where + ": measurements: " + what, "measurements");
  };
  if (!list.is_array()) bad("expected a JSON list of definitions");
  std::vector<MeasurementDefinition> defs;
  for (const auto& item : list) {
    if (!item.is_object() || !item.contains("name") || !item["name"].is_string() || !item.contains("kind") ||
        !item["kind"].is_string())
      bad("each definition needs a string 'name' and 'kind'");
    MeasurementDefinition d;
    d.name = item["name"].get<std::string>();
    try {
      d.kind = parse_measurement_kind(item["kind"].get<std::string>());
    } catch (const Error& e) {
      bad("'" + d.name + "': " + e.what());
    }
    if (item.contains("landmarks")) {
      if (!item["landmarks"].is_array()) bad("'" + d.name + "': landmarks must be a list of names");
      for (const auto& l : item["landmarks"]) {
        if (!l.is_string()) bad("'" + d.name + "': landmarks must be a list of names");
        d.landmarks.push_back(l.get<std::string>());
      }
    }
    if (item.contains("plane_normal")) {
      if (!item["plane_normal"].is_string()) bad("'" + d.name + "': plane_normal must be \"x\", \"y\" or \"z\"");
      try {
        d.plane_normal = parse_axis(item["plane_normal"].get<std::string>());
      } catch (const Error& e) {
        bad("'" + d.name + "': " + e.what());
      }
    }
    if (item.contains("description") && item["description"].is_string()) d.description = item["description"].get<std::string>();
    defs.push_back(std::move(d));
  }
  return defs;
}

json parse_json_text(const std::string& text, const std::string& where, const std::string& field) {
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    throw Error(ErrorKind::Format, where + ": " + field + " is not valid JSON: " + e.what(), field);
  }
}

// ---- native format ----

BodyModel native_from_arrays(const Arrays& f) {
  const std::string format = f.string("format");
  if (format != kFormatName) f.fail("format", "is '" + format + "', expected '" + kFormatName + "'");
  const auto version = f.indices("format_version", {}, 1, std::int64_t{1} << 31)[0];
  if (version > kFormatVersion)
    throw Error(ErrorKind::Unsupported, "'" + f.path() + "' uses model format version " + std::to_string(version) +
                                            "; this Caliper reads up to " + std::to_string(kFormatVersion), "format_version");

  BodyModelData d;
  d.name = f.string("name");
  const std::string sex = f.string("sex");
  if (sex != "female" && sex != "male" && sex != "neutral") f.fail("sex", "is '" + sex + "', expected female, male or neutral");
  d.sex = parse_sex(sex);

  const Array& tv = f.finite("template_vertices", {-1, 3});
  const std::int64_t n = tv.shape[0];
  d.template_vertices = Eigen::Map<const Vertices>(tv.numbers.data(), n, 3);

  const Array& faces_shape = f.numeric("faces", {-1, 3});
  const auto faces = f.indices("faces", {faces_shape.shape[0], 3}, 0, n);
  d.faces.resize(faces_shape.shape[0], 3);
  for (std::size_t k = 0; k < faces.size(); ++k) d.faces.data()[k] = static_cast<std::int32_t>(faces[k]);

  // N×3×K in C order is exactly the row-major 3N×K matrix (row 3v+c).
  const Array& sd = f.finite("shape_directions", {n, 3, -1});
  const std::int64_t k = sd.shape[2];
  d.shape_directions = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      sd.numbers.data(), 3 * n, k);

  const Array& parents_shape = f.numeric("parents", {-1});
  const std::int64_t j = parents_shape.shape[0];
  for (auto p : f.indices("parents", {j}, -1, j)) d.parents.push_back(static_cast<int>(p));
  d.joint_names = f.strings("joint_names", j);
  d.joint_regressor = read_sparse(f, "joint_regressor", false, j, n);
  d.skin_weights = read_sparse(f, "skin_weights", false, n, j);

  const Array& lv_shape = f.numeric("landmark_vertices", {-1});
  const std::int64_t l = lv_shape.shape[0];
  const auto lv = f.indices("landmark_vertices", {l}, 0, n);
  const auto ln = f.strings("landmark_names", l);
  for (std::int64_t i = 0; i < l; ++i) {
    if (!d.landmarks.emplace(ln[static_cast<std::size_t>(i)], static_cast<int>(lv[static_cast<std::size_t>(i)])).second)
      f.fail("landmark_names", "duplicate landmark '" + ln[static_cast<std::size_t>(i)] + "'");
  }

  read_uv_layout(f, d);

  d.measurements = definitions_from_json(parse_json_text(f.string("measurements"), f.path(), "measurements"), f.path());
  const Array& w = f.finite("weight_from_volume", {2});
  d.weight_from_volume = {w.numbers[0], w.numbers[1]};

  const json meta = parse_json_text(f.string("metadata"), f.path(), "metadata");
  if (!meta.is_object()) f.fail("metadata", "must be a JSON object of strings");
  for (const auto& [key, value] : meta.items()) {
    if (!value.is_string()) f.fail("metadata", "value of '" + key + "' is not a string");
    d.metadata[key] = value.get<std::string>();
  }
  return BodyModel(std::move(d));
}

// ---- SMPL / SMPL-X ----

// Joint names of the smplx package's SMPL-X (55) ordering; SMPL-H (52) is the same without
// jaw and eyes. The first 22 are SMPL's.
std::vector<std::string> smplx_joint_names(bool with_face) {
  std::vector<std::string> names(smpl_joint_names().begin(), smpl_joint_names().begin() + 22);
  if (with_face) names.insert(names.end(), {"jaw", "left_eye_smplhf", "right_eye_smplhf"});
  names.insert(names.end(), finger_joint_names().begin(), finger_joint_names().end());
  return names;
}

std::vector<std::string> joint_names_for(const Arrays& f, std::int64_t j) {
  if (f.has("joint_names")) {
    const Array& a = f.get("joint_names");
    if (!a.strings.empty()) return f.strings("joint_names", j);
  }
  if (j == 24) return smpl_joint_names();
  if (j == 55) return smplx_joint_names(true);
  if (j == 52) return smplx_joint_names(false);
  std::vector<std::string> names;
  for (std::int64_t i = 0; i < j; ++i) names.push_back("joint_" + std::to_string(i));
  return names;
}

void attach_smpl_landmarks(BodyModelData& d) {
  const json doc = json::parse(smpl_landmarks_json());
  for (const auto& [name, v] : doc.at("landmarks").items()) d.landmarks[name] = v.get<int>();
  for (auto& m : definitions_from_json(doc.at("measurements"), "landmarks/smpl.json")) {
    if (m.kind == MeasurementKind::Weight) continue;  // added for every topology below
    d.measurements.push_back(std::move(m));
  }
}

BodyModel smpl_from_arrays(const Arrays& f, const SmplLoadOptions& options) {
  if (options.shape_count < 1 || options.shape_count > kMaxSmplShapes)
    throw Error(ErrorKind::OutOfRange, "shape count must be in [1, " + std::to_string(kMaxSmplShapes) + "], got " +
                                           std::to_string(options.shape_count), "shape_count");
  BodyModelData d;
  d.name = options.name.empty() ? fs::path(f.path()).stem().string() : options.name;
  d.sex = options.sex;
  d.weight_from_volume = WeightFromVolume::paper(options.sex);

  const Array& tv = f.finite("v_template", {-1, 3});
  const std::int64_t n = tv.shape[0];
  if (n < 4) f.fail("v_template", "has " + std::to_string(n) + " vertices");
  d.template_vertices = Eigen::Map<const Vertices>(tv.numbers.data(), n, 3);

  const Array& sd = f.numeric("shapedirs", {n, 3, -1});
  const std::int64_t k_file = sd.shape[2];
  const int k = options.shape_count;
  if (k > k_file)
    throw Error(ErrorKind::OutOfRange, "'" + f.path() + "' has " + std::to_string(k_file) + " shape directions; " +
                                           std::to_string(k) + " were requested", "shape_count");
  d.shape_directions.resize(3 * n, k);
  for (std::int64_t r = 0; r < 3 * n; ++r)
    for (int c = 0; c < k; ++c) {
      const double v = sd.numbers[static_cast<std::size_t>(r * k_file + c)];
      if (!std::isfinite(v)) f.fail("shapedirs", "contains NaN or infinity");
      d.shape_directions(r, c) = v;
    }

  const Array& kt_shape = f.numeric("kintree_table", {2, -1});
  const std::int64_t j = kt_shape.shape[1];
  if (j < 1) f.fail("kintree_table", "has no joints");
  for (std::int64_t i = 0; i < j; ++i) {
    const double p = kt_shape.numbers[static_cast<std::size_t>(i)];
    const double id = kt_shape.numbers[static_cast<std::size_t>(j + i)];
    if (id != static_cast<double>(i))
      f.fail("kintree_table", "row 1 must list the joints 0.." + std::to_string(j - 1) + " in order");
    // The root's parent is -1, or -1 stored unsigned: 2^32-1 (uint32) or 2^64-1 (uint64).
    // float32 rounds 2^32-1 up to 2^32, so accept the whole band.
    const bool root_marker = p == -1.0 || (p >= 4294967295.0 && p <= 18446744073709551616.0);
    if (i == 0) {
      if (!root_marker) f.fail("kintree_table", "joint 0 must be the root (parent -1 or 2^32-1), has parent " + Arrays::number(p));
      d.parents.push_back(-1);
    } else {
      if (root_marker || p != std::floor(p) || p < 0 || p >= static_cast<double>(i))
        f.fail("kintree_table", "joint " + std::to_string(i) + " has parent " + Arrays::number(p) +
                                    " (parents must precede their children)");
      d.parents.push_back(static_cast<int>(p));
    }
  }
  d.joint_names = joint_names_for(f, j);

  if (f.has("J_regressor_data")) {
    bool csc = false;
    if (f.has("J_regressor_format")) {
      const std::string fmt = f.string("J_regressor_format");
      if (fmt != "csr" && fmt != "csc") f.fail("J_regressor_format", "is '" + fmt + "', expected 'csr' or 'csc'");
      csc = fmt == "csc";
    }
    d.joint_regressor = read_sparse(f, "J_regressor", csc, j, n);
  } else {
    if (f.has("J_regressor") && f.get("J_regressor").is_object) {
      f.fail("J_regressor", "is a pickled object (probably a scipy sparse matrix); store it dense or as "
                            "J_regressor_data/_indices/_indptr/_shape");
    }
    const Array& jr = f.finite("J_regressor", {j, n});
    std::vector<Eigen::Triplet<double>> t;
    for (std::int64_t r = 0; r < j; ++r)
      for (std::int64_t c = 0; c < n; ++c) {
        const double v = jr.numbers[static_cast<std::size_t>(r * n + c)];
        if (v != 0.0) t.emplace_back(static_cast<int>(r), static_cast<int>(c), v);
      }
    d.joint_regressor.resize(j, n);
    d.joint_regressor.setFromTriplets(t.begin(), t.end());
  }
  for (std::int64_t r = 0; r < j; ++r) {
    const double s = d.joint_regressor.row(r).sum();
    if (std::abs(s - 1.0) > 1e-3)
      f.fail(f.has("J_regressor_data") ? "J_regressor_data" : "J_regressor",
             "row " + std::to_string(r) + " sums to " + Arrays::number(s) + ", expected 1");
  }

  // Skinning weights: rows should sum to 1; float32 files are off by ~1e-7, so renormalise
  // small deviations and reject real inconsistencies.
  const Array& w = f.finite("weights", {n, j});
  std::vector<Eigen::Triplet<double>> wt;
  for (std::int64_t v = 0; v < n; ++v) {
    double s = 0;
    for (std::int64_t c = 0; c < j; ++c) {
      const double x = w.numbers[static_cast<std::size_t>(v * j + c)];
      if (x < -1e-6) f.fail("weights", "vertex " + std::to_string(v) + " has a negative weight " + Arrays::number(x));
      s += x;
    }
    if (std::abs(s - 1.0) > 1e-3)
      f.fail("weights", "vertex " + std::to_string(v) + " weights sum to " + Arrays::number(s) + ", expected 1");
    for (std::int64_t c = 0; c < j; ++c) {
      const double x = w.numbers[static_cast<std::size_t>(v * j + c)];
      if (x > 0.0) wt.emplace_back(static_cast<int>(v), static_cast<int>(c), x / s);
    }
  }
  d.skin_weights.resize(n, j);
  d.skin_weights.setFromTriplets(wt.begin(), wt.end());

  const Array& f_shape = f.numeric("f", {-1, 3});
  const auto faces = f.indices("f", {f_shape.shape[0], 3}, 0, n);
  d.faces.resize(f_shape.shape[0], 3);
  for (std::size_t i = 0; i < faces.size(); ++i) d.faces.data()[i] = static_cast<std::int32_t>(faces[i]);

  // Caliper stands bodies on y = 0 (SMPL's origin is near the pelvis). Joints follow, since
  // regressor rows sum to 1.
  const double floor_y = d.template_vertices.col(1).minCoeff();
  d.template_vertices.col(1).array() -= floor_y;

  if (n == 6890) attach_smpl_landmarks(d);
  d.measurements.push_back({"weight", MeasurementKind::Weight, {}, Axis::Y, "a * volume + b (paper section 3.4.2)"});

  d.metadata["source"] = fs::path(f.path()).filename().string();
  d.metadata["format"] = n == 10475 ? "smplx" : "smpl";
  d.metadata["licence"] = "SMPL / SMPL-X model licence (Max Planck Institute): non-commercial use; do not redistribute";
  d.metadata["shape_directions_in_file"] = std::to_string(k_file);
  d.metadata["y_offset_m"] = Arrays::number(-floor_y);
  return BodyModel(std::move(d));
}

std::string model_kind_error(const std::string& path) {
  return "'" + path + "' is neither a Caliper model (array 'format') nor an SMPL / SMPL-X file (array 'v_template')";
}

}  // namespace

void save_model(const BodyModel& model, const std::string& path) {
  const BodyModelData& d = model.data();
  const auto n = static_cast<std::int64_t>(d.template_vertices.rows());
  const auto k = static_cast<std::int64_t>(d.shape_directions.cols());
  const auto j = static_cast<std::int64_t>(d.joint_names.size());
  std::map<std::string, std::string> out;
  out["format"] = npz::write_npy_unicode(kFormatName);
  out["format_version"] = npz::write_npy_i64({kFormatVersion}, {});
  out["name"] = npz::write_npy_unicode(d.name);
  out["sex"] = npz::write_npy_unicode(to_string(d.sex));
  out["template_vertices"] = npz::write_npy_f64(
      std::vector<double>(d.template_vertices.data(), d.template_vertices.data() + d.template_vertices.size()), {n, 3});
  out["faces"] = npz::write_npy_i64(std::vector<std::int64_t>(d.faces.data(), d.faces.data() + d.faces.size()),
                                    {static_cast<std::int64_t>(d.faces.rows()), 3});
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> sd = d.shape_directions;
  out["shape_directions"] = npz::write_npy_f64(std::vector<double>(sd.data(), sd.data() + sd.size()), {n, 3, k});
  write_sparse(out, "joint_regressor", d.joint_regressor);
  write_sparse(out, "skin_weights", d.skin_weights);
  out["joint_names"] = npz::write_npy_unicode_array(d.joint_names, {j});
  out["parents"] = npz::write_npy_i64(std::vector<std::int64_t>(d.parents.begin(), d.parents.end()), {j});
  std::vector<std::string> landmark_names;
  std::vector<std::int64_t> landmark_vertices;
  for (const auto& [name, v] : d.landmarks) {
    landmark_names.push_back(name);
    landmark_vertices.push_back(v);
  }
  const auto l = static_cast<std::int64_t>(landmark_names.size());
  out["landmark_names"] = npz::write_npy_unicode_array(landmark_names, {l});
  out["landmark_vertices"] = npz::write_npy_i64(landmark_vertices, {l});
  out["measurements"] = npz::write_npy_unicode(definitions_to_json(d.measurements).dump());
  if (model.has_uvs()) {
    out["uv_coordinates"] = npz::write_npy_f64(
        std::vector<double>(d.uv_coordinates.data(), d.uv_coordinates.data() + d.uv_coordinates.size()),
        {static_cast<std::int64_t>(d.uv_coordinates.rows()), 2});
    out["uv_faces"] = npz::write_npy_i64(std::vector<std::int64_t>(d.uv_faces.data(), d.uv_faces.data() + d.uv_faces.size()),
                                         {static_cast<std::int64_t>(d.uv_faces.rows()), 3});
  }
  out["weight_from_volume"] = npz::write_npy_f64({d.weight_from_volume.a, d.weight_from_volume.b}, {2});
  json meta = json::object();
  for (const auto& [key, value] : d.metadata) meta[key] = value;
  out["metadata"] = npz::write_npy_unicode(meta.dump());
  npz::write_npz(path, out);
}

namespace {
// The reader itself; the public function below is its gate.
BodyModel read_native_model(const std::string& path) {
  const Arrays f(path, npz::read_npz(path));
  if (!f.has("format")) throw Error(ErrorKind::Format, "'" + path + "' is not a Caliper model: no array 'format'", "format");
  return native_from_arrays(f);
}
}  // namespace

BodyModel load_native_model(const std::string& path) {
  return gate("'" + path + "'", "model", [&] { return read_native_model(path); });
}

namespace {
// The reader itself; the public function below is its gate.
BodyModel read_smpl_model(const std::string& path, const SmplLoadOptions& options) {
  return smpl_from_arrays(Arrays(path, npz::read_npz(path)), options);
}
}  // namespace

BodyModel load_smpl_model(const std::string& path, const SmplLoadOptions& options) {
  return gate("'" + path + "'", "model", [&] { return read_smpl_model(path, options); });
}

std::string installed_data_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);  // Linux; elsewhere: not installed
  if (ec || exe.empty()) return "";
  const fs::path share = exe.parent_path().parent_path() / "share" / "caliper";
  return fs::is_directory(share, ec) ? share.string() : "";
}

namespace {
// `models/` beside the binary that holds this library, when there is one: the Python package's
// module (site-packages/caliper/_caliper….so → site-packages/caliper/models, put there by
// `pip install`). "" otherwise (a program's bin/ has none).
std::string models_beside_binary() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&models_dir), &info) == 0 || info.dli_fname == nullptr) return "";
  std::error_code ec;
  const fs::path dir = fs::absolute(info.dli_fname, ec).parent_path() / "models";
  return !ec && fs::is_directory(dir, ec) ? dir.string() : "";
}
}  // namespace

std::string models_dir() {
  const char* env = std::getenv("CALIPER_MODELS_DIR");
  if (env && *env) return env;
  if (std::string beside = models_beside_binary(); !beside.empty()) return beside;
  if (const std::string share = installed_data_dir(); !share.empty()) {
    std::error_code ec;
    if (fs::is_directory(fs::path(share) / "models", ec)) return (fs::path(share) / "models").string();
  }
  return CALIPER_MODELS_DIR;
}

namespace {
// A native or SMPL model, told apart by the arrays inside.
BodyModel read_any_model(const std::string& path, Sex sex) {
  const Arrays f(path, npz::read_npz(path));
  if (f.has("format")) return native_from_arrays(f);
  if (f.has("v_template")) {
    SmplLoadOptions options;
    options.sex = sex;
    return smpl_from_arrays(f, options);
  }
  throw Error(ErrorKind::Format, model_kind_error(path), "format");
}
}  // namespace

BodyModel load_model(const std::string& name_or_path, Sex sex) {
  std::error_code ec;
  auto load_path = [&](const std::string& path) { return gate("'" + path + "'", "model", [&] { return read_any_model(path, sex); }); };
  if (fs::is_regular_file(name_or_path, ec)) return load_path(name_or_path);

  const fs::path dir = models_dir();
  const bool looks_like_name = name_or_path.find('/') == std::string::npos && name_or_path.find('\\') == std::string::npos &&
                               !name_or_path.empty() && name_or_path != "." && name_or_path != "..";
  if (looks_like_name) {
    // The sex-specific variant first ("mannequin" + female → mannequin-female.npz), then the
    // family file itself. A model found by name is the installation's file, not the caller's.
    for (const fs::path& p : {dir / (name_or_path + "-" + to_string(sex) + ".npz"), dir / (name_or_path + ".npz")})
      if (fs::is_regular_file(p, ec))
        return installation_input([&] { return load_path(p.string()).supplied_by(ErrorOrigin::Installation); });
  }
  std::vector<std::string> available;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec) && it->path().extension() == ".npz") available.push_back(it->path().stem().string());
  std::sort(available.begin(), available.end());
  std::string list;
  for (const auto& a : available) list += (list.empty() ? "" : ", ") + a;
  throw Error(ErrorKind::Io,
              "no model file or model named '" + name_or_path + "' (models folder " + dir.string() + " has: " +
                  (list.empty() ? std::string("none") : list) + ")",
              "model");
}

}  // namespace caliper
