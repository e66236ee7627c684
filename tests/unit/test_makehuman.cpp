// The MakeHuman builder: asset parsing, the macro rule, rig mapping, landmarks and a
// small population build. Tests needing the assets read them from ../shared/data/makehuman and
// skip with a message where that folder is absent; the macro and bad-file tests need nothing.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <nlohmann/json.hpp>

#include "caliper/caliper.h"
#include "caliper/makehuman/assets.h"
#include "caliper/makehuman/body.h"
#include "caliper/makehuman/builder.h"
#include "caliper/makehuman/landmarks.h"
#include "caliper/makehuman/macro.h"
#include "caliper/measure/geometry.h"
#include "fixtures.h"
#include "temp_files.h"

namespace caliper {
namespace {

using test::kind_of;

using namespace makehuman;

std::string assets_dir() { return std::string(CALIPER_SHARED_DIR) + "/data/makehuman"; }
bool have_assets() { return std::filesystem::exists(assets_dir() + "/3dobjs/base.obj"); }
#define REQUIRE_ASSETS() \
  if (!have_assets()) GTEST_SKIP() << "MakeHuman assets not found in " << assets_dir() << " (see docs/makehuman.md)"

// Mesh and rig only (no targets): enough for the rig tests, and fast.
Assets mesh_and_rig() {
  Assets a;
  a.dir = assets_dir();
  a.mesh = read_base_mesh(a.dir);
  a.rig = read_rig(a.dir, a.mesh);
  return a;
}

void write_gz(const std::string& path, const std::string& text) {
  gzFile f = gzopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  gzwrite(f, text.data(), static_cast<unsigned>(text.size()));
  gzclose(f);
}

// ---- macro rule (no assets needed) ----

TEST(MakeHumanMacro, TargetWeightIsTheProductOfTokenWeights) {
  MacroSliders s;
  s.gender = 0.3;   // female 0.7, male 0.3
  s.age = 0.75;     // young 0.5, old 0.5
  s.muscle = 0.2;   // min 0.6, average 0.4
  s.weight = 0.25;  // min 0.5, average 0.5
  s.height = 0.8;   // maxheight 0.6, minheight 0
  s.african = 0.5, s.asian = 0.25, s.caucasian = 0.25;
  const auto w = token_weights(s);
  EXPECT_NEAR(target_weight("universal-female-old-minmuscle-averageweight", w), 0.7 * 0.5 * 0.6 * 0.5, 1e-12);
  EXPECT_NEAR(target_weight("african-male-young", w), 0.5 * 0.3 * 0.5, 1e-12);
  EXPECT_NEAR(target_weight("female-young-minmuscle-minweight-maxheight", w), 0.7 * 0.5 * 0.6 * 0.5 * 0.6, 1e-12);
  EXPECT_EQ(target_weight("male-old-averagemuscle-minweight-minheight", w), 0.0);
  EXPECT_EQ(target_weight("universal-male-baby-minmuscle-minweight", w), 0.0);
  // Race weights are normalised.
  s.african = 0.8, s.asian = 0.4, s.caucasian = 0.4;
  EXPECT_NEAR(token_weights(s).at("african"), 0.5, 1e-12);
}

TEST(MakeHumanMacro, AgeBreakpointsAndModifierSigns) {
  EXPECT_NEAR(age_slider(25), 0.5, 1e-12);
  EXPECT_NEAR(age_slider(10), 0.1875, 1e-12);
  EXPECT_NEAR(age_slider(90), 1.0, 1e-12);
  MacroSliders s;
  s.age = 0.1875;  // exactly a child
  EXPECT_NEAR(token_weights(s).at("child"), 1.0, 1e-12);
  EXPECT_NEAR(token_weights(s).at("young"), 0.0, 1e-12);
  const std::map<std::string, double> v = {{"measure-waist-circ", -0.4}};
  EXPECT_NEAR(modifier_weight("measure-waist-circ-decr", v), 0.4, 1e-12);
  EXPECT_EQ(modifier_weight("measure-waist-circ-incr", v), 0.0);
  EXPECT_EQ(modifier_weight("measure-hips-circ-incr", v), 0.0);
}

TEST(MakeHumanMacro, BadSlidersAndTokensAreErrors) {
  MacroSliders s;
  s.weight = 1.2;
  EXPECT_EQ(kind_of([&] { token_weights(s); }), ErrorKind::OutOfRange);
  s.weight = std::nan("");
  EXPECT_EQ(kind_of([&] { token_weights(s); }), ErrorKind::OutOfRange);
  s = {};
  s.african = s.asian = s.caucasian = 0;
  EXPECT_EQ(kind_of([&] { token_weights(s); }), ErrorKind::InvalidArgument);
  std::string message;
  EXPECT_EQ(kind_of([&] { target_weight("female-young-giant", token_weights(MacroSliders{})); }, &message), ErrorKind::Format);
  EXPECT_NE(message.find("giant"), std::string::npos);
}

// ---- bad files (no assets needed) ----

TEST(MakeHumanFiles, TargetParsesUnitsAndRejectsDamage) {
  test::TempDir dir;
  write_gz(dir / "good.target.gz", "0 1.0 -2.0 0.5\n# a comment\n7 0 0 .25\n");
  const Target t = read_target(dir / "good.target.gz", 10);
  EXPECT_EQ(t.name, "good");
  ASSERT_EQ(t.indices.size(), 2u);
  EXPECT_EQ(t.indices[1], 7);
  EXPECT_NEAR(t.deltas[0](1), -0.2, 1e-7);  // decimetres → metres
  EXPECT_NEAR(t.deltas[1](2), 0.025, 1e-7);

  std::string message;
  write_gz(dir / "range.target.gz", "0 0 0 0\n10 0 0 0\n");
  EXPECT_EQ(kind_of([&] { read_target(dir / "range.target.gz", 10); }, &message), ErrorKind::Format);
  EXPECT_NE(message.find("line 2"), std::string::npos) << message;
  write_gz(dir / "nan.target.gz", "3 0 nan 0\n");
  EXPECT_EQ(kind_of([&] { read_target(dir / "nan.target.gz", 10); }), ErrorKind::Format);
  write_gz(dir / "word.target.gz", "3 0 abc 0\n");
  EXPECT_EQ(kind_of([&] { read_target(dir / "word.target.gz", 10); }, &message), ErrorKind::Format);
  EXPECT_NE(message.find("abc"), std::string::npos);
  write_gz(dir / "fields.target.gz", "3 0 0\n");
  EXPECT_EQ(kind_of([&] { read_target(dir / "fields.target.gz", 10); }), ErrorKind::Format);
  // A displacement beyond float's range (found by fuzz_makehuman_target: it became infinite) and one
  // merely absurd are refused, quoted as written.
  for (const char* huge : {"1e53", "-250"}) {
    write_gz(dir / "huge.target.gz", std::string("3 0 ") + huge + " 0\n");
    EXPECT_EQ(kind_of([&] { read_target(dir / "huge.target.gz", 10); }, &message), ErrorKind::Format) << huge;
    EXPECT_NE(message.find(std::string("'") + huge + "' is outside [-100, 100]"), std::string::npos) << message;
  }

  // Not gzip at all, and a gzip stream cut in the middle.
  test::write_file(dir / "plain.target.gz", "0 1 2 3\n");
  EXPECT_EQ(kind_of([&] { read_target(dir / "plain.target.gz", 10); }, &message), ErrorKind::Format);
  EXPECT_NE(message.find("plain.target.gz"), std::string::npos);
  std::string big;
  for (int i = 0; i < 5000; ++i) big += std::to_string(i % 10) + " 0.123 0.456 0.789\n";
  write_gz(dir / "whole.target.gz", big);
  const std::string bytes = test::read_file(dir / "whole.target.gz");
  test::write_file(dir / "cut.target.gz", bytes.substr(0, bytes.size() / 2));
  EXPECT_EQ(kind_of([&] { read_target(dir / "cut.target.gz", 10); }), ErrorKind::Format);
  EXPECT_EQ(kind_of([&] { read_target(dir / "missing.target.gz", 10); }), ErrorKind::Io);
}

TEST(MakeHumanFiles, WrongFolderAndMissingFileAreClearErrors) {
  test::TempDir dir;
  std::string message;
  EXPECT_EQ(kind_of([&] { load_assets(dir / "nowhere"); }, &message), ErrorKind::Io);
  EXPECT_NE(message.find("MPFB2"), std::string::npos) << message;
  // A folder that is not an assets folder.
  EXPECT_EQ(kind_of([&] { load_assets(dir.path.string()); }, &message), ErrorKind::Io);
  EXPECT_NE(message.find("3dobjs"), std::string::npos) << message;
  // The right sub-folders but no base mesh.
  for (const char* sub : {"3dobjs", "mesh_metadata", "targets/macrodetails", "rigs/standard"})
    std::filesystem::create_directories(dir.path / sub);
  EXPECT_EQ(kind_of([&] { load_assets(dir.path.string()); }, &message), ErrorKind::Io);
  EXPECT_NE(message.find("base.obj"), std::string::npos) << message;
}

// The download as it comes: an unpacked archive of the MPFB2 repository, whose data folder is
// mpfb2-master/src/mpfb/data, gives the same assets as the data folder itself.
TEST(MakeHumanFiles, AcceptsTheRepositoryDownloadAsItComes) {
  REQUIRE_ASSETS();
  test::TempDir dir;
  const auto data = dir.path / "mpfb2-master" / "src" / "mpfb" / "data";
  std::filesystem::create_directories(data.parent_path());
  std::filesystem::create_directory_symlink(std::filesystem::absolute(assets_dir()), data);
  std::filesystem::create_directories(dir.path / "mpfb2-master" / "docs");  // a repository has more than its data
  const Assets direct = load_assets(assets_dir());
  for (const auto& given : {dir.path, dir.path / "mpfb2-master"}) {
    const Assets found = load_assets(given.string());
    EXPECT_EQ(std::filesystem::path(found.dir), data) << given;
    EXPECT_EQ(found.mesh.vertices.rows(), direct.mesh.vertices.rows()) << given;
    EXPECT_EQ(found.macro_targets.size(), direct.macro_targets.size()) << given;
    EXPECT_EQ(found.modifier_targets.size(), direct.modifier_targets.size()) << given;
  }
}

// Audit (docs/reliability.md): read_rig indexed missing keys of a const JSON object (undefined
// behaviour), let nlohmann's type_error escape for a wrong type, and cast 1e300 to int. Each is
// now Error(Format) naming the bone and key; a small rig on a four-vertex mesh shows it.
TEST(MakeHumanFiles, RigReaderChecksPresenceTypesAndRanges) {
  test::TempDir dir;
  std::filesystem::create_directories(dir.path / "rigs" / "standard");
  BaseMesh mesh;
  mesh.vertices = Vertices::Zero(4, 3);
  mesh.groups["joint-a"] = {1, 2};
  const std::string weights = R"({"weights": {"root": [[0, 1], [1, 1], [2, 1], [3, 1]]}})";
  const auto write_rig = [&](const std::string& rig, const std::string& w) {
    std::ofstream(dir / "rigs/standard/rig.test.json") << rig;
    std::ofstream(dir / "rigs/standard/weights.test.json") << w;
  };
  const auto field_of = [&](const std::string& rig, const std::string& w = "") {
    write_rig(rig, w.empty() ? weights : w);
    try {
      read_rig(dir.path.string(), mesh, "test");
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::Format) << e.what();
      return e.field();
    } catch (const std::exception& e) {
      return std::string("not a caliper::Error: ") + e.what();
    }
    return std::string("no error");
  };
  const std::string vertex0 = R"({"strategy": "VERTEX", "vertex_index": 0})";
  const auto root = [&](const std::string& head, const std::string& tail) {
    return R"({"root": {"head": )" + head + R"(, "tail": )" + tail + "}}";
  };
  write_rig(R"({"root": {"head": {"strategy": "CUBE", "cube_name": "joint-a"}, "tail": {"strategy": "MEAN", "vertex_indices": [1, 3.0]}}})",
            weights);
  const Rig ok = read_rig(dir.path.string(), mesh, "test");
  EXPECT_EQ(ok.bones.at(0).tail_vertices, (std::vector<int>{1, 3}));

  EXPECT_EQ(field_of(R"({"root": {"tail": )" + vertex0 + "}}"), "root.head");  // missing key
  EXPECT_EQ(field_of(R"({"root": 5})"), "root");
  EXPECT_EQ(field_of(root(R"({"vertex_index": 0})", vertex0)), "root.head.strategy");
  EXPECT_EQ(field_of(root(R"({"strategy": 5})", vertex0)), "root.head.strategy");  // wrong type
  EXPECT_EQ(field_of(root(R"({"strategy": "CUBE", "cube_name": 3})", vertex0)), "root.head.cube_name");
  EXPECT_EQ(field_of(root(vertex0, R"({"strategy": "VERTEX", "vertex_index": 1e300})")), "root.tail.vertex_index");
  EXPECT_EQ(field_of(root(vertex0, R"({"strategy": "VERTEX", "vertex_index": 4294967296})")), "root.tail.vertex_index");
  EXPECT_EQ(field_of(root(vertex0, R"({"strategy": "MEAN", "vertex_indices": ["1"]})")), "root.tail.vertex_indices");
  EXPECT_EQ(field_of(root(vertex0, R"({"strategy": "MEAN", "vertex_indices": [1e300]})")), "root.tail.vertex_indices");
  EXPECT_EQ(field_of(R"({"root": {"parent": 7, "head": )" + vertex0 + R"(, "tail": )" + vertex0 + "}}"), "root.parent");
  EXPECT_EQ(field_of(root(vertex0, vertex0), R"({"weights": {"root": [[1e300, 1]]}})"), "weights.root");
  EXPECT_EQ(field_of(root(vertex0, vertex0), R"({"weights": {"root": [["0", 1]]}})"), "weights.root");
  EXPECT_EQ(field_of(root(vertex0, vertex0), R"({"weights": {"root": 5}})"), "weights.root");
  EXPECT_EQ(field_of(root(vertex0, vertex0), R"({"bones": {}})"), "weights");
}

// Found while writing the rig fuzzer's oracle (docs/reliability.md "Fuzzing"; the input is kept in
// fuzz/regressions/makehuman_rig/): a weight of 1e308 is a finite double but overflows the float
// the rig keeps, so the vertex's weights became infinite and, once normalised, NaN. A weight is a fraction of its vertex: [0, 1], or an error naming the
// bone and the range.
TEST(MakeHumanFiles, RigWeightsAreFractionsOfTheirVertex) {
  test::TempDir dir;
  std::filesystem::create_directories(dir.path / "rigs" / "standard");
  BaseMesh mesh;
  mesh.vertices = Vertices::Zero(4, 3);
  std::ofstream(dir / "rigs/standard/rig.test.json")
      << R"({"root": {"head": {"strategy": "VERTEX", "vertex_index": 0}, "tail": {"strategy": "VERTEX", "vertex_index": 1}}})";
  const auto read_with = [&](const std::string& vertex0) {
    std::ofstream(dir / "rigs/standard/weights.test.json")
        << R"({"weights": {"root": [)" + vertex0 + R"(, [1, 1], [2, 1], [3, 1]]}})";
    return read_rig(dir.path.string(), mesh, "test");
  };
  for (const std::string bad : {"[0, 1e308], [0, 1e308]", "[0, 1.5]", "[0, -0.5]"}) {
    try {
      read_with(bad);
      ADD_FAILURE() << bad << ": accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::Format) << bad;
      EXPECT_EQ(e.field(), "weights.root") << bad;
      EXPECT_NE(std::string(e.what()).find("expected [0, 1]"), std::string::npos) << e.what();
      EXPECT_LT(std::string(e.what()).size(), 200u) << e.what();  // the number as written, not 309 digits
    }
  }
  // Two fractions of one vertex are normalised to sum 1.
  const Rig rig = read_with("[0, 0.25], [0, 0.5]");
  ASSERT_EQ(rig.weights.at(0).size(), 2u);
  EXPECT_FLOAT_EQ(rig.weights[0][0].second, 1.0f / 3);
  EXPECT_FLOAT_EQ(rig.weights[0][1].second, 2.0f / 3);
}

// ---- the real assets ----

TEST(MakeHumanAssets, BaseMeshIsClosedManifoldAndInMetres) {
  REQUIRE_ASSETS();
  const BaseMesh m = read_base_mesh(assets_dir());
  EXPECT_EQ(m.vertices.rows(), 19158);
  const MeshCheck c = check_mesh(m.body_faces, kBodyVertexCount);
  EXPECT_TRUE(c.closed && c.manifold && c.consistently_oriented);
  EXPECT_EQ(c.unused_vertices, 0);
  EXPECT_EQ(m.body_faces.maxCoeff(), kBodyVertexCount - 1);
  // README's independent reference numbers for the bare base mesh: 166.6 cm and 54.9 L.
  const Vertices body = m.vertices.topRows(kBodyVertexCount);
  EXPECT_NEAR((body.col(1).maxCoeff() - body.col(1).minCoeff()) * 100, 166.6, 0.06);
  EXPECT_NEAR(signed_volume(body, m.body_faces) * 1000, 54.9, 0.06);
  // The mirror map is an involution on the body.
  for (int v = 0; v < kBodyVertexCount; ++v) ASSERT_EQ(m.mirror[static_cast<size_t>(m.mirror[static_cast<size_t>(v)])], v);
}

TEST(MakeHumanAssets, BaseMeshTextureCoordinatesFollowTheFaces) {
  REQUIRE_ASSETS();
  const BaseMesh m = read_base_mesh(assets_dir());
  ASSERT_EQ(m.body_uv_faces.rows(), m.body_faces.rows());
  ASSERT_GT(m.body_uv.rows(), 0);
  EXPECT_GE(m.body_uv.minCoeff(), 0.0);
  EXPECT_LE(m.body_uv.maxCoeff(), 1.0);
  EXPECT_EQ(m.body_uv_faces.maxCoeff(), m.body_uv.rows() - 1);  // only the UVs the body uses
  // Independently: the file's first face is a body quad `f a/ta b/tb c/tc d/td`; its first
  // triangle (a, b, c) must carry ta, tb, tc (corners swapped together if the faces were).
  std::ifstream in(assets_dir() + "/3dobjs/base.obj");
  std::vector<std::array<double, 2>> vt;
  std::vector<std::pair<int, int>> quad;
  for (std::string line; std::getline(in, line) && quad.empty();) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "vt") {
      std::array<double, 2> t{};
      ls >> t[0] >> t[1];
      vt.push_back(t);
    } else if (key == "f") {
      for (std::string corner; ls >> corner;) {
        const size_t slash = corner.find('/');
        quad.push_back({std::stoi(corner.substr(0, slash)) - 1, std::stoi(corner.substr(slash + 1)) - 1});
      }
    }
  }
  ASSERT_GE(quad.size(), 3u);
  ASSERT_LT(quad[0].first, kBodyVertexCount);
  for (int c = 0; c < 3; ++c) {
    const int v = m.body_faces(0, c);
    const auto it = std::find_if(quad.begin(), quad.begin() + 3, [&](const auto& q) { return q.first == v; });
    ASSERT_NE(it, quad.begin() + 3) << "vertex " << v;
    EXPECT_EQ(m.body_uv(m.body_uv_faces(0, c), 0), vt[static_cast<size_t>(it->second)][0]);
    EXPECT_EQ(m.body_uv(m.body_uv_faces(0, c), 1), vt[static_cast<size_t>(it->second)][1]);
  }
}

TEST(MakeHumanAssets, MacroBodiesMatchTheReferenceNumbersAndTheTruncatedTargetIsNamed) {
  REQUIRE_ASSETS();
  const Assets a = load_assets(assets_dir());
  // README: young adult, race 1/3 each, other sliders 0.5: 159.0 cm / 48.0 L (gender 0),
  // 165.9 / 54.9 (0.5), 173.0 / 63.3 (1).
  const double expected[3][3] = {{0.0, 159.0, 48.0}, {0.5, 165.9, 54.9}, {1.0, 173.0, 63.3}};
  for (const auto& e : expected) {
    Shape s;
    s.macro.gender = e[0];
    const Vertices body = morph(a, s).topRows(kBodyVertexCount);
    EXPECT_NEAR((body.col(1).maxCoeff() - body.col(1).minCoeff()) * 100, e[1], 0.06) << "gender " << e[0];
    EXPECT_NEAR(signed_volume(body, a.mesh.body_faces) * 1000, e[2], 0.06) << "gender " << e[0];
  }
  bool named = false;
  for (const auto& p : a.problems) named |= p.name == "female-old-maxmuscle-maxweight-minheight";
  EXPECT_TRUE(named);
  for (const auto& t : a.macro_targets) EXPECT_NE(t.name, "female-old-maxmuscle-maxweight-minheight");
  EXPECT_EQ(modifier_names(a).size(), 20u);
  // A modifier moves the body: waist up, the waist's vertices move outwards on average.
  Shape wide;
  wide.modifiers["measure-waist-circ"] = 1;
  EXPECT_GT((morph(a, wide) - morph(a, Shape{})).cwiseAbs().maxCoeff(), 0.005);
}

TEST(MakeHumanRig, MapsOntoSmplJointsAndBakesAHorizontalTPose) {
  REQUIRE_ASSETS();
  const Assets a = mesh_and_rig();
  ASSERT_EQ(a.rig.bones.size(), 31u);
  const std::vector<int> of = smpl_joint_of_bones(a.rig);
  std::set<int> covered(of.begin(), of.end());
  EXPECT_EQ(covered.size(), 24u);  // every SMPL joint gets a bone
  const auto w = smpl_skin_weights(a);
  EXPECT_EQ(w.rows(), kBodyVertexCount);
  EXPECT_EQ(w.cols(), 24);
  for (int v = 0; v < kBodyVertexCount; ++v) ASSERT_NEAR(w.row(v).sum(), 1.0, 1e-6) << "vertex " << v;

  const PosedBody p = t_pose(a, a.mesh.vertices);
  const auto& names = smpl_joint_names();
  auto j = [&](const char* n) { return Eigen::Vector3d(p.joints.row(std::find(names.begin(), names.end(), n) - names.begin())); };
  for (const char* side : {"left", "right"}) {
    const std::string s(side);
    const double sign = s == "left" ? 1 : -1;
    const Eigen::Vector3d sh = j((s + "_shoulder").c_str()), el = j((s + "_elbow").c_str()), wr = j((s + "_wrist").c_str());
    EXPECT_NEAR(el(1), sh(1), 1e-9);  // arms horizontal
    EXPECT_NEAR(wr(1), sh(1), 1e-9);
    EXPECT_NEAR(el(2), sh(2), 1e-9);
    EXPECT_GT(sign * (el(0) - sh(0)), 0.2);  // pointing outwards
    EXPECT_GT(sign * (wr(0) - el(0)), 0.15);
  }
  EXPECT_NEAR(p.body.col(1).minCoeff(), 0.0, 1e-12);  // feet on the floor
  EXPECT_GT(j("left_foot")(2), j("left_ankle")(2));  // toes forward: facing +Z
  EXPECT_GT(j("left_hip")(0), 0);                      // +X is the body's left
  // The legs and head did not move: only the arm chains are posed.
  const double floor = a.mesh.vertices.topRows(kBodyVertexCount).col(1).minCoeff();
  const int head_vertex = 0;  // vertex 0 is on the face
  EXPECT_NEAR(p.body(head_vertex, 1) + floor, a.mesh.vertices(head_vertex, 1), 1e-12);
  EXPECT_NEAR(p.body(head_vertex, 0), a.mesh.vertices(head_vertex, 0), 1e-12);
}

TEST(MakeHumanLandmarks, JsonMatchesTheRulesSymmetricAndOrdered) {
  REQUIRE_ASSETS();
  const Assets a = load_assets(assets_dir());
  const std::map<std::string, int> picked = pick_landmarks(a);
  std::ifstream f(std::string(CALIPER_SOURCE_DIR) + "/landmarks/makehuman.json");
  ASSERT_TRUE(f) << "landmarks/makehuman.json missing";
  const nlohmann::json doc = nlohmann::json::parse(f);
  std::map<std::string, int> recorded;
  for (const auto& [k, v] : doc.at("landmarks").items()) recorded[k] = v.get<int>();
  EXPECT_EQ(picked, recorded);
  // Every landmark the measurement definitions use exists.
  for (const auto& d : measurement_definitions())
    for (const auto& l : d.landmarks) EXPECT_TRUE(picked.count(l)) << d.name << " needs " << l;

  const BodyModel ref = reference_model(a, Sex::Neutral);
  const Vertices& v = ref.data().template_vertices;
  for (const auto& [name, idx] : picked) {
    const auto pos = name.rfind("_left");
    if (pos == std::string::npos || pos + 5 != name.size()) continue;
    if (!picked.count(name.substr(0, pos) + "_right")) continue;  // e.g. hip_left has no partner
    const int right = picked.at(name.substr(0, pos) + "_right");
    EXPECT_EQ(a.mesh.mirror[static_cast<size_t>(idx)], right) << name;
    EXPECT_NEAR(v(idx, 0), -v(right, 0), 1e-3) << name;
    EXPECT_NEAR(v(idx, 1), v(right, 1), 1e-3) << name;
    EXPECT_GT(v(idx, 0), 0) << name << " is on the body's left (+X)";
  }
  const char* order[] = {"vertex", "glabella", "neck_front", "cervicale", "acromion_right", "axilla_right", "thelion_right",
                         "omphalion", "trochanterion_right", "crotch", "gluteal_furrow", "knee_right", "calf_right",
                         "ankle_right", "lateral_malleolus_right"};
  for (size_t i = 0; i + 1 < std::size(order); ++i)
    EXPECT_GT(v(picked.at(order[i]), 1), v(picked.at(order[i + 1]), 1)) << order[i] << " above " << order[i + 1];
  // The reference body measures like a person of its height.
  const auto m = measure_all(ref, v);
  EXPECT_GT(m.at("span") / m.at("stature"), 0.9);
  EXPECT_GT(m.at("hip_breadth"), 0.28);
  EXPECT_LT(m.at("hand_breadth"), 0.11);
}

TEST(MakeHumanBuild, SmallPopulationGivesAModelAvatarsCanUse) {
  REQUIRE_ASSETS();
  const std::string csv = std::string(CALIPER_SHARED_DIR) + "/data/ansur2/ANSUR_II_FEMALE_dev.csv";
  if (!std::filesystem::exists(csv)) GTEST_SKIP() << "ANSUR II data not found: " << csv;
  const Assets a = load_assets(assets_dir());
  const auto subjects = read_ansur_csv(csv);
  BuildOptions o;
  o.components = 3;
  o.max_subjects = 12;
  o.iterations = 4;
  BuildReport rep;
  auto model = std::make_shared<const BodyModel>(build_makehuman_model(a, subjects, Sex::Female, o, &rep));
  EXPECT_EQ(rep.subjects, 12);
  EXPECT_EQ(model->name(), "makehuman-female");
  EXPECT_EQ(model->vertex_count(), kBodyVertexCount);
  EXPECT_EQ(model->shape_count(), 3);
  EXPECT_EQ(model->joint_count(), 24);
  EXPECT_GT(rep.fitted.a, 0);
  EXPECT_FALSE(rep.problems.empty());
  // The fit moved the bodies towards the subjects: stature is fitted to within a few cm.
  EXPECT_LT(rep.fit_mae.at("stature"), 0.03);
  // The joint regressor reproduces the rig's joints on the fitted bodies.
  EXPECT_LT(rep.joint_rms_m, 0.01);
  const Vertices mean = model->rest_vertices(Eigen::VectorXd::Zero(3));
  EXPECT_NEAR(mean.col(1).minCoeff(), 0.0, 0.01);
  const Eigen::MatrixX3d joints = model->joints(mean);
  EXPECT_NEAR(joints(18, 1), joints(16, 1), 0.02);  // elbows level with shoulders: T-pose

  AvatarBuilder builder(model);
  AvatarRequest request;
  request.measurements = {{"stature", 1.66}, {"weight", 64.0}};
  request.regressor = "R2";
  request.measure_only = {"stature", "weight"};
  const Avatar av = builder.build(request);
  EXPECT_NEAR(av.achieved.at("stature"), 1.66, 0.005);
  EXPECT_NEAR(av.achieved.at("weight"), 64.0, 1.0);

  test::TempDir dir;
  save_model(*model, dir / "makehuman-female.npz");
  const BodyModel back = load_model(dir / "makehuman-female.npz", Sex::Female);
  EXPECT_EQ(back.vertex_count(), model->vertex_count());
  EXPECT_EQ(back.data().landmarks, model->data().landmarks);
  // MakeHuman's own UV layout travels with the model.
  ASSERT_TRUE(model->has_uvs());
  EXPECT_EQ(back.data().uv_faces, model->data().uv_faces);
  EXPECT_EQ(back.data().uv_coordinates, model->data().uv_coordinates);
}

}  // namespace
}  // namespace caliper
