// SMPL / SMPL-X loading from synthetic SMPL-shaped files (never a real SMPL file): every storage
// variant users' files come in, and a clear error naming the array for each kind of breakage.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <set>

#include "caliper/errors.h"
#include "temp_files.h"
#include "caliper/io/model_files.h"
#include "caliper/io/npz.h"
#include "caliper/export/gltf.h"
#include "caliper/vocabulary/catalogue.h"

using namespace caliper;
using test::TempDir;
using test::read_file;
using test::write_file;
namespace fs = std::filesystem;

namespace {


// .npy bytes of `values` stored as `descr` (little-endian f4, f8, i4, i8 or u4).
std::string encode(const std::string& descr, const std::vector<std::int64_t>& shape, const std::vector<double>& values) {
  std::string shape_text = "(";
  for (std::size_t k = 0; k < shape.size(); ++k) shape_text += (k ? ", " : "") + std::to_string(shape[k]);
  shape_text += shape.size() == 1 ? ",)" : ")";
  const std::string dict = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + shape_text + ", }\n";
  std::string out = std::string("\x93NUMPY\x01\x00", 8);
  out += static_cast<char>(dict.size() & 0xFF);
  out += static_cast<char>(dict.size() >> 8);
  out += dict;
  for (double v : values) {
    char b[8];
    std::size_t n = 8;
    if (descr == "<f4") { const float f = static_cast<float>(v); std::memcpy(b, &f, 4); n = 4; }
    else if (descr == "<f8") std::memcpy(b, &v, 8);
    else if (descr == "<i4") { const auto i = static_cast<std::int32_t>(v); std::memcpy(b, &i, 4); n = 4; }
    else if (descr == "<i8") { const auto i = static_cast<std::int64_t>(v); std::memcpy(b, &i, 8); }
    else if (descr == "<u4") { const auto u = static_cast<std::uint32_t>(v); std::memcpy(b, &u, 4); n = 4; }
    else throw std::logic_error("encode: unsupported " + descr);
    out.append(b, n);
  }
  return out;
}

std::string pickle_npy() {
  const std::string dict = "{'descr': '|O', 'fortran_order': False, 'shape': (), }\n";
  // Protocol-2 pickle bytes of a dict; the loader must skip them without interpreting them.
  return std::string("\x93NUMPY\x01\x00", 8) + static_cast<char>(dict.size()) + '\0' + dict + std::string("\x80\x02}q\x00.", 6);
}

enum class Root { MinusOneInt64, Uint32Max, Float64, Float32 };

struct Fixture {
  int n = 8, j = 24, k = 10;
  bool f32 = false;
  enum { Dense, Csr, Csc } regressor = Dense;
  Root root = Root::MinusOneInt64;
  std::string faces_dtype = "<i8";
  std::vector<std::string> joint_names;  // written when non-empty
  double weight_scale = 1.0;             // multiplies every skinning weight

  // Exact in float32, so f32 and f64 files must load to the same numbers.
  double vx(int v, int c) const { return c == 0 ? (v % 7) / 64.0 : c == 1 ? -1.25 + (v % 200) / 128.0 : (v % 5) / 32.0; }
  double dir(int v, int c, int kk) const { return ((v * 3 + c) % 13 - 6) / 256.0 + kk / 1024.0; }
  std::vector<int> parents() const {
    if (j == 24) return smpl_parents();
    std::vector<int> p(static_cast<std::size_t>(j));
    for (int i = 0; i < j; ++i) p[static_cast<std::size_t>(i)] = i - 1;
    return p;
  }

  std::map<std::string, std::string> entries() const {
    const std::string fl = f32 ? "<f4" : "<f8";
    std::map<std::string, std::string> e;
    std::vector<double> tv, sd;
    for (int v = 0; v < n; ++v)
      for (int c = 0; c < 3; ++c) {
        tv.push_back(vx(v, c));
        for (int kk = 0; kk < k; ++kk) sd.push_back(dir(v, c, kk));
      }
    e["v_template"] = encode(fl, {n, 3}, tv);
    e["shapedirs"] = encode(fl, {n, 3, k}, sd);
    e["posedirs"] = encode(fl, {n, 3, 1}, std::vector<double>(static_cast<std::size_t>(3 * n), 0.0));

    // Joint r averages vertices r and r+1 (mod n) with weights 1/4, 3/4.
    if (regressor == Dense) {
      std::vector<double> jr(static_cast<std::size_t>(j * n), 0.0);
      for (int r = 0; r < j; ++r) {
        jr[static_cast<std::size_t>(r * n + r % n)] += 0.25;
        jr[static_cast<std::size_t>(r * n + (r + 1) % n)] += 0.75;
      }
      e["J_regressor"] = encode(fl, {j, n}, jr);
    } else {
      std::vector<double> data, indices, indptr = {0};
      if (regressor == Csr) {
        for (int r = 0; r < j; ++r) {
          int a = r % n, b = (r + 1) % n;
          double wa = 0.25, wb = 0.75;
          if (b < a) { std::swap(a, b); std::swap(wa, wb); }
          data.insert(data.end(), {wa, wb});
          indices.insert(indices.end(), {double(a), double(b)});
          indptr.push_back(static_cast<double>(data.size()));
        }
      } else {
        e["J_regressor_format"] = npz::write_npy_unicode("csc");
        for (int col = 0; col < n; ++col) {
          for (int r = 0; r < j; ++r) {
            if (r % n == col) { data.push_back(0.25); indices.push_back(r); }
            if ((r + 1) % n == col) { data.push_back(0.75); indices.push_back(r); }
          }
          indptr.push_back(static_cast<double>(data.size()));
        }
      }
      const auto nnz = static_cast<std::int64_t>(data.size());
      e["J_regressor_data"] = encode(fl, {nnz}, data);
      e["J_regressor_indices"] = encode("<i4", {nnz}, indices);
      e["J_regressor_indptr"] = encode("<i4", {static_cast<std::int64_t>(indptr.size())}, indptr);
      e["J_regressor_shape"] = encode("<i8", {2}, {double(j), double(n)});
    }

    std::vector<double> w(static_cast<std::size_t>(n * j), 0.0);
    for (int v = 0; v < n; ++v) {
      w[static_cast<std::size_t>(v * j + v % j)] += 0.5 * weight_scale;
      w[static_cast<std::size_t>(v * j + (v + 1) % j)] += 0.5 * weight_scale;
    }
    e["weights"] = encode(fl, {n, j}, w);

    std::vector<double> kt;
    const auto p = parents();
    for (int i = 0; i < j; ++i) kt.push_back(i == 0 ? (root == Root::MinusOneInt64 ? -1.0 : 4294967295.0) : p[static_cast<std::size_t>(i)]);
    for (int i = 0; i < j; ++i) kt.push_back(i);
    const std::string kd = root == Root::MinusOneInt64 ? "<i8" : root == Root::Uint32Max ? "<u4" : root == Root::Float64 ? "<f8" : "<f4";
    e["kintree_table"] = encode(kd, {2, j}, kt);

    std::vector<double> f;
    for (int t = 0; t + 2 < n; ++t) f.insert(f.end(), {double(t), double(t + 1), double(t + 2)});
    e["f"] = encode(faces_dtype, {n - 2, 3}, f);

    e["joint2num"] = pickle_npy();
    e["bs_style"] = pickle_npy();
    if (!joint_names.empty()) e["joint_names"] = npz::write_npy_unicode_array(joint_names, {static_cast<std::int64_t>(joint_names.size())});
    return e;
  }

  std::string write(const TempDir& dir, const std::string& name = "smpl_test.npz") const {
    const std::string path = dir / name;
    npz::write_npz(path, entries());
    return path;
  }
};

Error smpl_error(const std::string& path, const SmplLoadOptions& options = {}) {
  try {
    load_smpl_model(path, options);
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "loading " << path << " did not throw";
  return Error(ErrorKind::Unsupported, "none");
}

Error broken(const TempDir& dir, const Fixture& fx, const std::function<void(std::map<std::string, std::string>&)>& edit) {
  auto e = fx.entries();
  edit(e);
  npz::write_npz(dir / "broken.npz", e);
  return smpl_error(dir / "broken.npz");
}

void expect_fixture_geometry(const BodyModel& m, const Fixture& fx) {
  ASSERT_EQ(m.vertex_count(), fx.n);
  ASSERT_EQ(m.joint_count(), fx.j);
  ASSERT_EQ(m.face_count(), fx.n - 2);
  const auto& d = m.data();
  // Stood on the floor: SMPL's y shifted so the lowest vertex is at 0; x, z untouched.
  for (int v = 0; v < fx.n; ++v) {
    EXPECT_EQ(d.template_vertices(v, 0), fx.vx(v, 0));
    EXPECT_EQ(d.template_vertices(v, 1), fx.vx(v, 1) + 1.25);
    EXPECT_EQ(d.template_vertices(v, 2), fx.vx(v, 2));
  }
  for (int v = 0; v < fx.n; ++v)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < m.shape_count(); ++k) ASSERT_EQ(d.shape_directions(3 * v + c, k), fx.dir(v, c, k));
  for (int r = 0; r < fx.j; ++r) {
    EXPECT_EQ(d.joint_regressor.coeff(r, r % fx.n), 0.25);
    EXPECT_EQ(d.joint_regressor.coeff(r, (r + 1) % fx.n), 0.75);
  }
  EXPECT_EQ(d.joint_regressor.nonZeros(), 2 * fx.j);
  for (int v = 0; v < fx.n; ++v) EXPECT_DOUBLE_EQ(d.skin_weights.row(v).sum(), 1.0);
  EXPECT_EQ(d.skin_weights.coeff(3, 3), 0.5);
  EXPECT_EQ(d.skin_weights.coeff(3, 4), 0.5);
  EXPECT_EQ(d.faces(2, 0), 2);
  EXPECT_EQ(d.faces(2, 2), 4);
  EXPECT_EQ(d.parents, fx.parents());
}

}  // namespace

TEST(SmplLoader, LoadsFloat64DenseWithPickledExtras) {
  TempDir dir;
  Fixture fx;
  SmplLoadOptions options;
  options.sex = Sex::Male;
  const BodyModel m = load_smpl_model(fx.write(dir), options);
  expect_fixture_geometry(m, fx);
  EXPECT_EQ(m.name(), "smpl_test");
  EXPECT_EQ(m.sex(), Sex::Male);
  EXPECT_EQ(m.data().weight_from_volume.a, 1056.44);
  EXPECT_EQ(m.data().weight_from_volume.b, -5.28);
  EXPECT_EQ(m.data().joint_names, smpl_joint_names());
  EXPECT_EQ(m.shape_count(), 10);
}

TEST(SmplLoader, LoadsFloat32SparseAndEveryRootMarker) {
  TempDir dir;
  for (auto reg : {Fixture::Csr, Fixture::Csc})
    for (Root root : {Root::MinusOneInt64, Root::Uint32Max, Root::Float64, Root::Float32}) {
      Fixture fx;
      fx.f32 = true;
      fx.regressor = reg;
      fx.root = root;
      fx.faces_dtype = root == Root::Float32 ? "<f4" : "<u4";
      SCOPED_TRACE("regressor " + std::to_string(int(reg)) + " root " + std::to_string(int(root)));
      expect_fixture_geometry(load_smpl_model(fx.write(dir)), fx);
    }
}

TEST(SmplLoader, KeepsTheRequestedNumberOfShapeDirections) {
  TempDir dir;
  Fixture fx;
  fx.k = 300;
  const std::string path = fx.write(dir);
  SmplLoadOptions options;
  options.name = "named";
  for (int k : {10, 300}) {
    options.shape_count = k;
    const BodyModel m = load_smpl_model(path, options);
    EXPECT_EQ(m.shape_count(), k);
    EXPECT_EQ(m.name(), "named");
    EXPECT_EQ(m.data().shape_directions(3 * 5 + 1, k - 1), fx.dir(5, 1, k - 1));
  }
  for (int k : {301, 0, 401, -3}) {
    options.shape_count = k;
    const Error e = smpl_error(path, options);
    EXPECT_EQ(e.kind(), ErrorKind::OutOfRange) << k;
    EXPECT_EQ(e.field(), "shape_count") << k;
  }
}

TEST(SmplLoader, JointNamesForEachFamily) {
  TempDir dir;
  Fixture smplx;
  smplx.j = 55;
  smplx.n = 60;
  const auto names = load_smpl_model(smplx.write(dir)).data().joint_names;
  ASSERT_EQ(names.size(), 55u);
  EXPECT_EQ(names[21], "right_wrist");
  EXPECT_EQ(names[22], "jaw");
  EXPECT_EQ(names[25], "left_index1");
  EXPECT_EQ(names[54], "right_thumb3");
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), 55u);

  Fixture own = smplx;
  for (int i = 0; i < 55; ++i) own.joint_names.push_back(std::string("j").append(std::to_string(i)));
  EXPECT_EQ(load_smpl_model(own.write(dir)).data().joint_names, own.joint_names);

  Fixture odd;
  odd.j = 5;
  EXPECT_EQ(load_smpl_model(odd.write(dir)).data().joint_names,
            (std::vector<std::string>{"joint_0", "joint_1", "joint_2", "joint_3", "joint_4"}));
}

TEST(SmplLoader, AttachesSmplLandmarksOnlyForSmplTopology) {
  TempDir dir;
  Fixture small;
  const BodyModel s = load_smpl_model(small.write(dir));
  EXPECT_TRUE(s.data().landmarks.empty());
  ASSERT_EQ(s.data().measurements.size(), 1u);  // only weight, which needs no landmark
  EXPECT_EQ(s.data().measurements[0].kind, MeasurementKind::Weight);
  EXPECT_EQ(s.find_measurement("stature"), nullptr);

  Fixture smpl;
  smpl.n = 6890;
  const BodyModel m = load_smpl_model(smpl.write(dir));
  EXPECT_EQ(m.landmark("vertex"), 412);
  EXPECT_EQ(m.landmark("heel_left"), 3458);
  ASSERT_NE(m.find_measurement("stature"), nullptr);
  EXPECT_EQ(m.find_measurement("stature")->landmarks, (std::vector<std::string>{"vertex"}));
  ASSERT_NE(m.find_measurement("weight"), nullptr);
  int weights = 0;
  for (const auto& d : m.data().measurements) weights += d.kind == MeasurementKind::Weight;
  EXPECT_EQ(weights, 1);
}

TEST(SmplLoader, EmbeddedLandmarksMatchTheJsonFileAndAreConsistent) {
  const auto embedded = nlohmann::json::parse(smpl_landmarks_json());
  std::ifstream in(std::string(CALIPER_SOURCE_DIR) + "/landmarks/smpl.json");
  ASSERT_TRUE(in) << "landmarks/smpl.json not found";
  EXPECT_EQ(embedded, nlohmann::json::parse(in));

  std::set<std::string> names;
  for (const auto& [name, v] : embedded.at("landmarks").items()) {
    names.insert(name);
    EXPECT_GE(v.get<int>(), 0) << name;
    EXPECT_LT(v.get<int>(), 6890) << name;
  }
  for (const char* required : {"vertex", "heel_left", "heel_right", "acromion_left", "acromion_right", "wrist_left",
                               "wrist_right", "dactylion_left", "dactylion_right", "thelion_left", "thelion_right",
                               "omphalion", "crotch"})
    EXPECT_TRUE(names.count(required)) << required;
  std::set<std::string> measurement_names;
  for (const auto& m : embedded.at("measurements")) {
    const std::string name = m.at("name");
    EXPECT_TRUE(measurement_names.insert(name).second) << "duplicate " << name;
    EXPECT_NE(find_measurement_info(name), nullptr) << name << " is not in the measurement catalogue";
    for (const auto& l : m.at("landmarks")) EXPECT_TRUE(names.count(l.get<std::string>())) << name << " uses " << l;
  }
  for (const char* paper : {"stature", "weight", "span", "crotch_height", "hip_breadth", "arm_length"})
    EXPECT_TRUE(measurement_names.count(paper)) << paper;
}

TEST(SmplLoader, NormalisesWeightsOnlyWhenNearlyNormalised) {
  TempDir dir;
  Fixture fx;
  fx.weight_scale = 1.0 + 5e-4;
  const BodyModel m = load_smpl_model(fx.write(dir));
  for (int v = 0; v < fx.n; ++v) EXPECT_NEAR(m.data().skin_weights.row(v).sum(), 1.0, 1e-14);
  fx.weight_scale = 0.9;
  const Error e = smpl_error(fx.write(dir));
  EXPECT_EQ(e.kind(), ErrorKind::Format);
  EXPECT_EQ(e.field(), "weights");
}

TEST(SmplLoader, BrokenFilesGiveErrorsNamingTheArray) {
  TempDir dir;
  const Fixture fx;
  for (const std::string missing : {"v_template", "shapedirs", "J_regressor", "weights", "kintree_table", "f"}) {
    const Error e = broken(dir, fx, [&](auto& m) { m.erase(missing); });
    EXPECT_EQ(e.kind(), ErrorKind::Format) << missing;
    EXPECT_EQ(e.field(), missing);
  }
  std::vector<double> tv(24, 0.5);
  tv[7] = std::nan("");
  Error e = broken(dir, fx, [&](auto& m) { m["v_template"] = encode("<f8", {8, 3}, tv); });
  EXPECT_EQ(e.field(), "v_template");
  EXPECT_NE(std::string(e.what()).find("NaN"), std::string::npos) << e.what();

  std::vector<double> f;
  for (int t = 0; t < 6; ++t) f.insert(f.end(), {double(t), double(t + 1), t == 3 ? 8.0 : double(t + 2)});
  e = broken(dir, fx, [&](auto& m) { m["f"] = encode("<i4", {6, 3}, f); });
  EXPECT_EQ(e.field(), "f");
  f[9] = -1;
  EXPECT_EQ(broken(dir, fx, [&](auto& m) { m["f"] = encode("<i4", {6, 3}, f); }).field(), "f");

  // Wrong shapes.
  e = broken(dir, fx, [&](auto& m) { m["weights"] = encode("<f8", {8, 25}, std::vector<double>(200, 0.04)); });
  EXPECT_EQ(e.field(), "weights");
  e = broken(dir, fx, [&](auto& m) { m["shapedirs"] = encode("<f8", {8, 2, 10}, std::vector<double>(160, 0.0)); });
  EXPECT_EQ(e.field(), "shapedirs");
  e = broken(dir, fx, [&](auto& m) { m["J_regressor"] = encode("<f8", {24, 9}, std::vector<double>(216, 1.0 / 9)); });
  EXPECT_EQ(e.field(), "J_regressor");
  e = broken(dir, fx, [&](auto& m) { m["v_template"] = encode("<f8", {24}, std::vector<double>(24, 0.0)); });
  EXPECT_EQ(e.field(), "v_template");

  // A child listed before its parent, and a second root.
  std::vector<double> kt;
  for (int i = 0; i < 24; ++i) kt.push_back(i == 0 ? -1 : i == 5 ? 7 : smpl_parents()[static_cast<std::size_t>(i)]);
  for (int i = 0; i < 24; ++i) kt.push_back(i);
  e = broken(dir, fx, [&](auto& m) { m["kintree_table"] = encode("<i8", {2, 24}, kt); });
  EXPECT_EQ(e.field(), "kintree_table");
  kt[5] = 4294967295.0;
  EXPECT_EQ(broken(dir, fx, [&](auto& m) { m["kintree_table"] = encode("<f8", {2, 24}, kt); }).field(), "kintree_table");

  // A regressor row that does not sum to 1.
  std::vector<double> jr(24 * 8, 0.0);
  for (int r = 0; r < 24; ++r) jr[static_cast<std::size_t>(r * 8)] = r == 3 ? 0.5 : 1.0;
  EXPECT_EQ(broken(dir, fx, [&](auto& m) { m["J_regressor"] = encode("<f8", {24, 8}, jr); }).field(), "J_regressor");

  // Sparse parts out of range, unknown sparse format, pickled dense regressor.
  Fixture csr;
  csr.regressor = Fixture::Csr;
  e = broken(dir, csr, [&](auto& m) { m["J_regressor_indices"] = encode("<i4", {48}, std::vector<double>(48, 8.0)); });
  EXPECT_EQ(e.field(), "J_regressor_indices");
  e = broken(dir, csr, [&](auto& m) { m["J_regressor_format"] = npz::write_npy_unicode("coo"); });
  EXPECT_EQ(e.field(), "J_regressor_format");
  e = broken(dir, csr, [&](auto& m) { m["J_regressor_shape"] = encode("<i8", {2}, {24, 9}); });
  EXPECT_EQ(e.field(), "J_regressor_shape");
  e = broken(dir, fx, [&](auto& m) { m["J_regressor"] = pickle_npy(); });
  EXPECT_EQ(e.field(), "J_regressor");
  EXPECT_NE(std::string(e.what()).find("pickled"), std::string::npos) << e.what();

  // Strings where numbers belong.
  e = broken(dir, fx, [&](auto& m) { m["f"] = npz::write_npy_unicode("faces"); });
  EXPECT_EQ(e.field(), "f");
}

// Audit (docs/reliability.md): a sparse regressor whose declared shape has no rows, or 2^31 − 1
// of them, once crashed `caliper model info` (entries placed outside a 0-row matrix) or grew to
// 8 GB (Eigen's row offsets) before any check. Now the shape must be (J, N) and every index fits
// it, checked before anything is built.
TEST(SmplLoader, SparseShapesAreCheckedBeforeAnythingIsBuilt) {
  TempDir dir;
  Fixture csc;
  csc.regressor = Fixture::Csc;
  const auto nnz = static_cast<std::int64_t>(2 * csc.j);
  const auto zeros = encode("<i4", {nnz}, std::vector<double>(static_cast<std::size_t>(nnz), 0.0));
  for (const std::vector<double>& shape : {std::vector<double>{0, 8}, {2147483647.0, 8}, {24, 2147483647.0}}) {
    const Error e = broken(dir, csc, [&](auto& m) {
      m["J_regressor_shape"] = encode("<i8", {2}, shape);
      m["J_regressor_indices"] = zeros;  // every entry in row 0: in range for any shape with rows
    });
    EXPECT_EQ(e.kind(), ErrorKind::Format) << shape[0];
    EXPECT_EQ(e.field(), "J_regressor_shape") << e.what();
    EXPECT_NE(std::string(e.what()).find("expected (24, 8)"), std::string::npos) << e.what();
  }
  Fixture csr;
  csr.regressor = Fixture::Csr;
  const Error e = broken(dir, csr, [&](auto& m) {
    m["J_regressor_shape"] = encode("<i8", {2}, {24, 0});
    m["J_regressor_indices"] = zeros;
  });
  EXPECT_EQ(e.field(), "J_regressor_shape") << e.what();
}

TEST(SmplLoader, NotAZipAndTruncatedFiles) {
  TempDir dir;
  std::ofstream(dir / "text.npz") << "v_template = [[0, 0, 0]]\n";
  EXPECT_EQ(smpl_error(dir / "text.npz").kind(), ErrorKind::Format);
  EXPECT_EQ(smpl_error(dir / "absent.npz").kind(), ErrorKind::Io);

  Fixture fx;
  std::ifstream in(fx.write(dir), std::ios::binary);
  const std::string whole{std::istreambuf_iterator<char>(in), {}};
  for (std::size_t cut = 1; cut < whole.size(); cut += whole.size() / 23) {
    std::ofstream(dir / "cut.npz", std::ios::binary) << whole.substr(0, cut);
    EXPECT_EQ(smpl_error(dir / "cut.npz").kind(), ErrorKind::Format) << "cut at " << cut;
  }
}

TEST(SmplLoader, LoadModelDetectsSmplFiles) {
  TempDir dir;
  Fixture fx;
  const BodyModel m = load_model(fx.write(dir, "SMPL_FEMALE.npz"), Sex::Female);
  EXPECT_EQ(m.name(), "SMPL_FEMALE");
  EXPECT_EQ(m.sex(), Sex::Female);
  EXPECT_EQ(m.data().weight_from_volume.a, 1001.44);
  EXPECT_EQ(m.data().metadata.at("format"), "smpl");
}

// An avatar made from an SMPL file keeps SMPL's non-commercial licence inside the exported file.
TEST(SmplLoader, ExportedGlbSaysNonCommercial) {
  TempDir dir;
  Fixture fx;
  const BodyModel m = load_smpl_model(fx.write(dir));
  const std::string glb = write_glb(m, m.data().template_vertices);
  std::uint32_t length = 0;
  std::memcpy(&length, glb.data() + 12, 4);
  const auto doc = nlohmann::json::parse(glb.substr(20, length));
  const std::string copyright = doc["asset"]["copyright"];
  EXPECT_NE(copyright.find("non-commercial use only"), std::string::npos) << copyright;
  EXPECT_NE(copyright.find("SMPL"), std::string::npos) << copyright;
  EXPECT_EQ(doc["asset"]["extras"]["caliper"]["commercial_use"], false);
  EXPECT_EQ(doc["asset"]["extras"]["caliper"]["body_model"], "smpl_test");
}
