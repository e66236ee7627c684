// Caliper's native model format: exact round trip of a hand-built model, reproducible bytes, the
// documented array layout, clear errors for broken files, and lookup by name in the models folder.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

#include "caliper/errors.h"
#include "temp_files.h"
#include "caliper/io/model_files.h"
#include "caliper/io/npz.h"

using namespace caliper;
using test::TempDir;
using test::read_file;
using test::write_file;
namespace fs = std::filesystem;

namespace {



// A regular octahedron (6 vertices, 8 outward faces) with two joints and two shape directions.
// Values are chosen to be inexact in binary (0.1, 1/3…) so a lossy round trip would show.
BodyModelData octahedron_data() {
  BodyModelData d;
  d.name = "octa-test";
  d.sex = Sex::Female;
  d.template_vertices.resize(6, 3);
  d.template_vertices << 0.1, 0.5, 0.0,   // +X
      -0.1, 0.5, 0.0,                     // −X
      0.0, 0.6, 0.0,                      // top
      0.0, 0.4, 0.0,                      // bottom
      0.0, 0.5, 1.0 / 3.0,                // +Z
      0.0, 0.5, -1.0 / 3.0;               // −Z
  d.faces.resize(8, 3);
  d.faces << 0, 2, 4, 4, 2, 1, 1, 2, 5, 5, 2, 0, 4, 3, 0, 1, 3, 4, 5, 3, 1, 0, 3, 5;
  d.shape_directions.resize(18, 2);
  for (int r = 0; r < 18; ++r) {
    d.shape_directions(r, 0) = 0.01 * std::sin(r + 1.0);
    d.shape_directions(r, 1) = -1e-3 / (r + 7.0);
  }
  d.joint_names = {"pelvis", "head"};
  d.parents = {-1, 0};
  std::vector<Eigen::Triplet<double>> jr = {{0, 0, 0.5}, {0, 1, 0.5}, {1, 2, 0.7}, {1, 4, 0.1}, {1, 5, 0.2}};
  d.joint_regressor.resize(2, 6);
  d.joint_regressor.setFromTriplets(jr.begin(), jr.end());
  std::vector<Eigen::Triplet<double>> sw = {{0, 0, 1.0}, {1, 0, 1.0}, {2, 1, 1.0}, {3, 0, 1.0},
                                            {4, 0, 0.3}, {4, 1, 0.7}, {5, 0, 0.9}, {5, 1, 0.1}};
  d.skin_weights.resize(6, 2);
  d.skin_weights.setFromTriplets(sw.begin(), sw.end());
  d.landmarks = {{"vertex", 2}, {"floor_point", 3}, {"front", 4}, {"side_left", 0}};
  d.measurements = {{"stature", MeasurementKind::Height, {"vertex"}, Axis::Y, "top above floor"},
                    {"span", MeasurementKind::Length, {"side_left", "front", "vertex"}, Axis::Y, ""},
                    {"wrist_circumference", MeasurementKind::Circumference, {"front"}, Axis::X, "tape, \"quoted\" é"},
                    {"weight", MeasurementKind::Weight, {}, Axis::Y, ""}};
  d.weight_from_volume = {1001.44, -2.36};
  d.metadata = {{"licence", "CC0"}, {"source", "hand-built \xe2\x80\x94 test"}};
  return d;
}

bool same_bits(const double* a, const double* b, std::size_t n) { return std::memcmp(a, b, n * sizeof(double)) == 0; }

void expect_sparse_identical(const Eigen::SparseMatrix<double, Eigen::RowMajor>& a,
                             const Eigen::SparseMatrix<double, Eigen::RowMajor>& b) {
  ASSERT_EQ(a.rows(), b.rows());
  ASSERT_EQ(a.cols(), b.cols());
  ASSERT_EQ(a.nonZeros(), b.nonZeros());
  EXPECT_TRUE(same_bits(a.valuePtr(), b.valuePtr(), static_cast<std::size_t>(a.nonZeros())));
  EXPECT_EQ(std::memcmp(a.innerIndexPtr(), b.innerIndexPtr(), sizeof(int) * static_cast<std::size_t>(a.nonZeros())), 0);
  EXPECT_EQ(std::memcmp(a.outerIndexPtr(), b.outerIndexPtr(), sizeof(int) * static_cast<std::size_t>(a.rows() + 1)), 0);
}

// Re-encodes arrays read back from a file (numbers as f8, strings as unicode) so a test can
// break one array and write the file again.
std::map<std::string, std::string> reencode(const std::map<std::string, npz::Array>& arrays) {
  std::map<std::string, std::string> out;
  for (const auto& [name, a] : arrays) {
    if (!a.strings.empty() || a.dtype[1] == 'U') out[name] = npz::write_npy_unicode_array(a.strings, a.shape);
    else out[name] = npz::write_npy_f64(a.numbers, a.shape);
  }
  return out;
}

Error load_error(const std::string& path) {
  try {
    load_native_model(path);
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "loading " << path << " did not throw";
  return Error(ErrorKind::Unsupported, "none");
}

// The error from loading `good`'s arrays re-encoded and changed by `edit`, written to dir/broken.npz.
using ArrayEdit = std::function<void(std::map<std::string, std::string>&)>;
Error load_edited_error(const TempDir& dir, const std::map<std::string, npz::Array>& good, const ArrayEdit& edit) {
  auto entries = reencode(good);
  edit(entries);
  npz::write_npz(dir / "broken.npz", entries);
  return load_error(dir / "broken.npz");
}

// Sets an environment variable for one scope.
struct ScopedEnv {
  std::string name;
  std::string old;
  bool had = false;
  ScopedEnv(std::string n, const std::string& value) : name(std::move(n)) {
    if (const char* v = std::getenv(name.c_str())) {
      had = true;
      old = v;
    }
    setenv(name.c_str(), value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (had) setenv(name.c_str(), old.c_str(), 1);
    else unsetenv(name.c_str());
  }
};

}  // namespace

TEST(NativeModel, RoundTripIsExact) {
  TempDir dir;
  const BodyModel model(octahedron_data());
  save_model(model, dir / "octa.npz");
  const BodyModel back = load_native_model(dir / "octa.npz");
  const auto& a = model.data();
  const auto& b = back.data();
  EXPECT_EQ(b.name, "octa-test");
  EXPECT_EQ(b.sex, Sex::Female);
  ASSERT_EQ(b.template_vertices.rows(), 6);
  EXPECT_TRUE(same_bits(a.template_vertices.data(), b.template_vertices.data(), 18));
  EXPECT_EQ(a.faces, b.faces);
  ASSERT_EQ(b.shape_directions.rows(), 18);
  ASSERT_EQ(b.shape_directions.cols(), 2);
  EXPECT_TRUE(same_bits(a.shape_directions.data(), b.shape_directions.data(), 36));
  expect_sparse_identical(a.joint_regressor, b.joint_regressor);
  expect_sparse_identical(a.skin_weights, b.skin_weights);
  EXPECT_EQ(a.joint_names, b.joint_names);
  EXPECT_EQ(a.parents, b.parents);
  EXPECT_EQ(a.landmarks, b.landmarks);
  ASSERT_EQ(a.measurements.size(), b.measurements.size());
  for (std::size_t k = 0; k < a.measurements.size(); ++k) {
    EXPECT_EQ(a.measurements[k].name, b.measurements[k].name);
    EXPECT_EQ(a.measurements[k].kind, b.measurements[k].kind);
    EXPECT_EQ(a.measurements[k].landmarks, b.measurements[k].landmarks);
    EXPECT_EQ(a.measurements[k].plane_normal, b.measurements[k].plane_normal);
    EXPECT_EQ(a.measurements[k].description, b.measurements[k].description);
  }
  EXPECT_EQ(b.weight_from_volume.a, 1001.44);
  EXPECT_EQ(b.weight_from_volume.b, -2.36);
  EXPECT_EQ(a.metadata, b.metadata);
}

TEST(NativeModel, SameModelGivesSameBytes) {
  TempDir dir;
  const BodyModel model(octahedron_data());
  save_model(model, dir / "one.npz");
  save_model(model, dir / "two.npz");
  const std::string one = read_file(dir / "one.npz");
  EXPECT_FALSE(one.empty());
  EXPECT_EQ(one, read_file(dir / "two.npz"));
  // Loading and saving again changes nothing either.
  save_model(load_native_model(dir / "one.npz"), dir / "three.npz");
  EXPECT_EQ(one, read_file(dir / "three.npz"));
}

TEST(NativeModel, ArraysHaveTheDocumentedNamesShapesAndLayout) {
  TempDir dir;
  const BodyModel model(octahedron_data());
  save_model(model, dir / "octa.npz");
  const auto arrays = npz::read_npz(dir / "octa.npz");
  const std::vector<std::string> expected = {
      "faces", "format", "format_version", "joint_names", "joint_regressor_data", "joint_regressor_indices",
      "joint_regressor_indptr", "joint_regressor_shape", "landmark_names", "landmark_vertices", "measurements", "metadata",
      "name", "parents", "sex", "shape_directions", "skin_weights_data", "skin_weights_indices", "skin_weights_indptr",
      "skin_weights_shape", "template_vertices", "weight_from_volume"};
  std::vector<std::string> names;
  for (const auto& [name, a] : arrays) names.push_back(name);
  EXPECT_EQ(names, expected);
  EXPECT_EQ(arrays.at("format").strings, (std::vector<std::string>{"caliper-body-model"}));
  EXPECT_EQ(arrays.at("format_version").numbers, (std::vector<double>{1}));
  EXPECT_EQ(arrays.at("template_vertices").dtype, "<f8");
  EXPECT_EQ(arrays.at("template_vertices").shape, (std::vector<std::int64_t>{6, 3}));
  EXPECT_EQ(arrays.at("faces").dtype, "<i8");
  EXPECT_EQ(arrays.at("faces").shape, (std::vector<std::int64_t>{8, 3}));
  EXPECT_EQ(arrays.at("parents").numbers, (std::vector<double>{-1, 0}));
  EXPECT_EQ(arrays.at("joint_regressor_shape").numbers, (std::vector<double>{2, 6}));
  EXPECT_EQ(arrays.at("skin_weights_indptr").numbers, (std::vector<double>{0, 1, 2, 3, 4, 6, 8}));
  EXPECT_EQ(arrays.at("landmark_names").strings, (std::vector<std::string>{"floor_point", "front", "side_left", "vertex"}));
  EXPECT_EQ(arrays.at("landmark_vertices").numbers, (std::vector<double>{3, 4, 0, 2}));
  // SMPL's shapedirs layout: element [v][c][k] is coordinate c of vertex v in direction k.
  const auto& sd = arrays.at("shape_directions");
  EXPECT_EQ(sd.shape, (std::vector<std::int64_t>{6, 3, 2}));
  for (int v = 0; v < 6; ++v)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 2; ++k)
        EXPECT_EQ(sd.numbers[static_cast<std::size_t>((v * 3 + c) * 2 + k)], model.data().shape_directions(3 * v + c, k));
}

TEST(NativeModel, BrokenFilesGiveErrorsNamingTheArray) {
  TempDir dir;
  save_model(BodyModel(octahedron_data()), dir / "octa.npz");
  const auto good = npz::read_npz(dir / "octa.npz");
  const auto broken = [&](const ArrayEdit& edit) { return load_edited_error(dir, good, edit); };
  // Re-encoded as-is it still loads: the edits below are what break it.
  npz::write_npz(dir / "reencoded.npz", reencode(good));
  EXPECT_EQ(load_native_model(dir / "reencoded.npz").vertex_count(), 6);

  for (const std::string missing : {"faces", "template_vertices", "shape_directions", "joint_regressor_indptr", "parents",
                                    "landmark_names", "measurements", "weight_from_volume", "metadata", "name"}) {
    const Error e = broken([&](auto& m) { m.erase(missing); });
    EXPECT_EQ(e.kind(), ErrorKind::Format) << missing;
    EXPECT_EQ(e.field(), missing);
    EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
  }
  auto tv = good.at("template_vertices").numbers;
  tv[4] = std::nan("");
  Error e = broken([&](auto& m) { m["template_vertices"] = npz::write_npy_f64(tv, {6, 3}); });
  EXPECT_EQ(e.field(), "template_vertices");
  EXPECT_NE(std::string(e.what()).find("NaN"), std::string::npos);

  e = broken([&](auto& m) { m["template_vertices"] = npz::write_npy_f64(std::vector<double>(12, 0.0), {6, 2}); });
  EXPECT_EQ(e.field(), "template_vertices");
  EXPECT_NE(std::string(e.what()).find("shape"), std::string::npos);

  auto faces = good.at("faces").numbers;
  faces[5] = 6;  // one past the last vertex
  e = broken([&](auto& m) { m["faces"] = npz::write_npy_f64(faces, {8, 3}); });
  EXPECT_EQ(e.field(), "faces");
  faces[5] = 2.5;
  EXPECT_EQ(broken([&](auto& m) { m["faces"] = npz::write_npy_f64(faces, {8, 3}); }).field(), "faces");

  e = broken([&](auto& m) { m["shape_directions"] = npz::write_npy_f64(std::vector<double>(12, 0.0), {2, 3, 2}); });
  EXPECT_EQ(e.field(), "shape_directions");

  e = broken([&](auto& m) { m["parents"] = npz::write_npy_i64({-1, 1}, {2}); });  // joint 1 its own parent
  EXPECT_EQ(e.field(), "parents");

  e = broken([&](auto& m) { m["joint_regressor_indices"] = npz::write_npy_i64({0, 1, 2, 4, 9}, {5}); });
  EXPECT_EQ(e.field(), "joint_regressor_indices");

  e = broken([&](auto& m) { m["format"] = npz::write_npy_unicode("something-else"); });
  EXPECT_EQ(e.field(), "format");
  EXPECT_EQ(e.kind(), ErrorKind::Format);

  e = broken([&](auto& m) { m["format_version"] = npz::write_npy_i64({2}, {}); });
  EXPECT_EQ(e.kind(), ErrorKind::Unsupported);
  EXPECT_EQ(e.field(), "format_version");

  e = broken([&](auto& m) { m["measurements"] = npz::write_npy_unicode("[{\"name\": \"stature\""); });
  EXPECT_EQ(e.field(), "measurements");
  e = broken([&](auto& m) { m["measurements"] = npz::write_npy_unicode("[{\"name\": \"x\", \"kind\": \"volume\"}]"); });
  EXPECT_EQ(e.field(), "measurements");
  e = broken([&](auto& m) { m["metadata"] = npz::write_npy_unicode("[1, 2]"); });
  EXPECT_EQ(e.field(), "metadata");
  e = broken([&](auto& m) { m["sex"] = npz::write_npy_unicode("x"); });
  EXPECT_EQ(e.field(), "sex");
  // A pickled array where numbers belong.
  e = broken([&](auto& m) {
    const std::string dict = "{'descr': '|O', 'fortran_order': False, 'shape': (), }\n";
    m["faces"] = std::string("\x93NUMPY\x01\x00", 8) + static_cast<char>(dict.size()) + '\0' + dict + "\x80\x02N.";
  });
  EXPECT_EQ(e.field(), "faces");
  EXPECT_NE(std::string(e.what()).find("pickled"), std::string::npos) << e.what();
}

// Audit (docs/reliability.md): skin weights declared N × 0 with every index 0 once crashed the
// loader (entries placed in a matrix without columns). The sparse shapes must be (J, N) and
// (N, J), and the indices fit them, before anything is built.
TEST(NativeModel, SparseShapesMustMatchTheModel) {
  TempDir dir;
  save_model(BodyModel(octahedron_data()), dir / "octa.npz");
  const auto good = npz::read_npz(dir / "octa.npz");
  const auto broken = [&](const std::string& prefix, std::vector<std::int64_t> shape) {
    auto entries = reencode(good);
    const auto nnz = static_cast<std::int64_t>(good.at(prefix + "_data").numbers.size());
    entries[prefix + "_shape"] = npz::write_npy_i64(shape, {2});
    entries[prefix + "_indices"] = npz::write_npy_i64(std::vector<std::int64_t>(static_cast<std::size_t>(nnz), 0), {nnz});
    npz::write_npz(dir / "broken.npz", entries);
    return load_error(dir / "broken.npz");
  };
  for (const auto& shape : {std::vector<std::int64_t>{6, 0}, {0, 2}, {6, 2147483647}}) {
    const Error e = broken("skin_weights", shape);
    EXPECT_EQ(e.kind(), ErrorKind::Format);
    EXPECT_EQ(e.field(), "skin_weights_shape") << e.what();
    EXPECT_NE(std::string(e.what()).find("expected (6, 2)"), std::string::npos) << e.what();
  }
  const Error e = broken("joint_regressor", {2, 0});
  EXPECT_EQ(e.field(), "joint_regressor_shape") << e.what();
}

TEST(NativeModel, TruncatedFilesNeverCrash) {
  TempDir dir;
  save_model(BodyModel(octahedron_data()), dir / "octa.npz");
  const std::string whole = read_file(dir / "octa.npz");
  for (std::size_t cut = 0; cut < whole.size(); cut += 97) {
    std::ofstream(dir / "cut.npz", std::ios::binary) << whole.substr(0, cut);
    EXPECT_EQ(load_error(dir / "cut.npz").kind(), ErrorKind::Format) << "cut at " << cut;
  }
}

TEST(LoadModel, ByPathAndByNameInTheModelsFolder) {
  TempDir dir;
  ScopedEnv env("CALIPER_MODELS_DIR", dir.path.string());
  EXPECT_EQ(models_dir(), dir.path.string());

  BodyModelData female = octahedron_data();
  female.name = "toy-female";
  save_model(BodyModel(female), dir / "toy-female.npz");
  BodyModelData plain = octahedron_data();
  plain.name = "toy";
  plain.sex = Sex::Neutral;
  save_model(BodyModel(plain), dir / "toy.npz");
  BodyModelData other = octahedron_data();
  other.name = "solo";
  save_model(BodyModel(other), dir / "solo.npz");

  EXPECT_EQ(load_model(dir / "solo.npz", Sex::Male).name(), "solo");  // a path: the file's own model
  EXPECT_EQ(load_model("toy", Sex::Female).name(), "toy-female");      // the sex picks the variant
  EXPECT_EQ(load_model("toy", Sex::Male).name(), "toy");               // no male variant: the family file
  EXPECT_EQ(load_model("toy-female", Sex::Male).name(), "toy-female");
  EXPECT_EQ(load_model("solo", Sex::Neutral).name(), "solo");

  try {
    load_model("nobody", Sex::Female);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Io);
    const std::string msg = e.what();
    EXPECT_NE(msg.find("nobody"), std::string::npos) << msg;
    EXPECT_NE(msg.find("solo, toy, toy-female"), std::string::npos) << msg;
  }
  try {
    load_model(dir / "missing/file.npz", Sex::Female);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Io);
  }
  // An npz that is neither kind of model.
  npz::write_npz(dir / "other.npz", {{"x", npz::write_npy_f64({1}, {1})}});
  try {
    load_model(dir / "other.npz", Sex::Female);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Format);
    EXPECT_NE(std::string(e.what()).find("v_template"), std::string::npos) << e.what();
  }
}

// ---- the optional UV layout -------------------------------------------------------------------

namespace {

// The octahedron with a UV layout: 8 faces, each its own triangle of 3 UVs (inexact values).
BodyModelData octahedron_with_uvs() {
  BodyModelData d = octahedron_data();
  d.uv_coordinates.resize(24, 2);
  for (int i = 0; i < 24; ++i) d.uv_coordinates.row(i) << (i % 6) / 7.0 + 0.01 * (i / 6), (i / 6) / 4.0 + 0.1 * (i % 2);
  d.uv_faces.resize(8, 3);
  for (int f = 0; f < 8; ++f) d.uv_faces.row(f) << 3 * f + 2, 3 * f, 3 * f + 1;
  return d;
}

}  // namespace

TEST(NativeModelUvs, RoundTripIsExact) {
  TempDir dir;
  const BodyModel original(octahedron_with_uvs());
  save_model(original, dir / "octa-uv.npz");
  const auto arrays = npz::read_npz(dir / "octa-uv.npz");
  EXPECT_EQ(arrays.at("uv_coordinates").dtype, "<f8");
  EXPECT_EQ(arrays.at("uv_coordinates").shape, (std::vector<std::int64_t>{24, 2}));
  EXPECT_EQ(arrays.at("uv_faces").dtype, "<i8");
  EXPECT_EQ(arrays.at("uv_faces").shape, (std::vector<std::int64_t>{8, 3}));
  const BodyModel loaded = load_native_model(dir / "octa-uv.npz");
  ASSERT_TRUE(loaded.has_uvs());
  const auto& a = original.data().uv_coordinates;
  const auto& b = loaded.data().uv_coordinates;
  ASSERT_EQ(a.rows(), b.rows());
  EXPECT_TRUE(same_bits(a.data(), b.data(), static_cast<std::size_t>(a.size())));
  EXPECT_EQ(loaded.data().uv_faces, original.data().uv_faces);
  // Saving the loaded model gives the same bytes.
  save_model(loaded, dir / "again.npz");
  EXPECT_EQ(read_file(dir / "octa-uv.npz"), read_file(dir / "again.npz"));
}

TEST(NativeModelUvs, FilesWithoutThemStillLoad) {
  TempDir dir;
  save_model(BodyModel(octahedron_data()), dir / "octa.npz");
  const auto arrays = npz::read_npz(dir / "octa.npz");
  EXPECT_EQ(arrays.count("uv_coordinates"), 0u);  // nothing written for a model without UVs
  EXPECT_EQ(arrays.count("uv_faces"), 0u);
  EXPECT_FALSE(load_native_model(dir / "octa.npz").has_uvs());
}

TEST(NativeModelUvs, BrokenLayoutsAreRefusedNamingTheArray) {
  TempDir dir;
  save_model(BodyModel(octahedron_with_uvs()), dir / "octa-uv.npz");
  const auto good = npz::read_npz(dir / "octa-uv.npz");
  const auto broken = [&](const ArrayEdit& edit) { return load_edited_error(dir, good, edit); };
  npz::write_npz(dir / "reencoded.npz", reencode(good));
  EXPECT_TRUE(load_native_model(dir / "reencoded.npz").has_uvs());

  auto expect_format = [](const Error& e, const std::string& field, const std::string& words) {
    EXPECT_EQ(e.kind(), ErrorKind::Format) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  };
  // One without the other.
  expect_format(broken([](auto& m) { m.erase("uv_faces"); }), "uv_faces", "missing");
  expect_format(broken([](auto& m) { m.erase("uv_coordinates"); }), "uv_coordinates", "missing");
  // uv_faces with a row too few or too many (the face count is 8).
  auto uf = good.at("uv_faces").numbers;
  expect_format(broken([&](auto& m) { m["uv_faces"] = npz::write_npy_f64(std::vector<double>(uf.begin(), uf.end() - 3), {7, 3}); }),
                "uv_faces", "shape");
  auto longer = uf;
  longer.insert(longer.end(), {0, 1, 2});
  expect_format(broken([&](auto& m) { m["uv_faces"] = npz::write_npy_f64(longer, {9, 3}); }), "uv_faces", "shape");
  // An index out of range, negative, or not an integer.
  auto bad = uf;
  bad[4] = 24;
  expect_format(broken([&](auto& m) { m["uv_faces"] = npz::write_npy_f64(bad, {8, 3}); }), "uv_faces", "[0, 24)");
  bad[4] = -1;
  expect_format(broken([&](auto& m) { m["uv_faces"] = npz::write_npy_f64(bad, {8, 3}); }), "uv_faces", "not an integer");
  bad[4] = 1.5;
  expect_format(broken([&](auto& m) { m["uv_faces"] = npz::write_npy_f64(bad, {8, 3}); }), "uv_faces", "not an integer");
  // Coordinates outside [0, 1], NaN, the wrong shape, or more rows than face corners.
  auto uv = good.at("uv_coordinates").numbers;
  uv[7] = 1.25;
  expect_format(broken([&](auto& m) { m["uv_coordinates"] = npz::write_npy_f64(uv, {24, 2}); }), "uv_coordinates", "outside");
  uv[7] = std::nan("");
  expect_format(broken([&](auto& m) { m["uv_coordinates"] = npz::write_npy_f64(uv, {24, 2}); }), "uv_coordinates", "NaN");
  expect_format(broken([&](auto& m) { m["uv_coordinates"] = npz::write_npy_f64(std::vector<double>(72, 0.5), {24, 3}); }),
                "uv_coordinates", "shape");
  expect_format(broken([&](auto& m) { m["uv_coordinates"] = npz::write_npy_f64(std::vector<double>(50, 0.5), {25, 2}); }),
                "uv_coordinates", "rows");
}
