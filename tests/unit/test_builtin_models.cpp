// Invariants over the committed built-in body models (models/mannequin-*.npz): topology,
// landmarks, joints, sampled bodies, regressors and posing on the real thing.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#ifdef CALIPER_HAVE_ASSIMP
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#endif

#include "caliper/caliper.h"
#include "caliper/mannequin/population.h"

using namespace caliper;

namespace {

class BuiltinModel : public ::testing::TestWithParam<Sex> {
 protected:
  static std::shared_ptr<const BodyModel> model(Sex sex) {
    static std::map<Sex, std::shared_ptr<const BodyModel>> cache;
    auto& m = cache[sex];
    if (!m) m = std::make_shared<const BodyModel>(load_model("mannequin", sex));
    return m;
  }
};

double height_of(const BodyModel& m, const Vertices& v, const std::string& name) {
  return measure(m, *m.find_measurement(name), v);
}

}  // namespace

// The estimator weighs the body through its volume polynomial: it must be the mesh's volume, and
// its gradient the mesh volume's gradient through the shape directions, for bodies across the
// population (β up to 3 SD).
TEST_P(BuiltinModel, VolumePolynomialIsTheMeshsVolume) {
  const auto m = model(GetParam());
  const VolumePolynomial poly(*m);
  std::mt19937 rng(7);
  std::normal_distribution<double> normal(0.0, 1.5);
  for (int body = 0; body < 6; ++body) {
    Eigen::VectorXd beta(m->shape_count());
    for (Eigen::Index i = 0; i < beta.size(); ++i) beta(i) = std::clamp(normal(rng), -3.0, 3.0);
    const Vertices rest = m->rest_vertices(beta);
    Eigen::VectorXd dense;
    const double volume = signed_volume(rest, m->faces(), dense);
    const Eigen::RowVectorXd mesh_gradient = dense.transpose() * m->data().shape_directions;
    Eigen::RowVectorXd gradient;
    // rest_vertices adds S·β in single precision: about 1e-8 m per vertex, 1e-7 of the volume.
    EXPECT_NEAR(poly.value(beta, &gradient), volume, 1e-6 * volume) << "body " << body;
    EXPECT_LT((gradient - mesh_gradient).cwiseAbs().maxCoeff(), 1e-5 * mesh_gradient.cwiseAbs().maxCoeff())
        << "body " << body;
  }
}

TEST_P(BuiltinModel, CountsAndTopology) {
  const auto m = model(GetParam());
  EXPECT_GE(m->vertex_count(), 10000);
  EXPECT_LE(m->vertex_count(), 25000);
  EXPECT_EQ(m->joint_count(), 54);
  EXPECT_EQ(m->data().joint_names, rig_joint_names());
  // The committed models are built with the documented default K (scripts/build-models.sh).
  EXPECT_EQ(m->shape_count(), mannequin::PopulationOptions{}.components);
  const MeshCheck c = check_mesh(m->faces(), m->vertex_count());
  EXPECT_TRUE(c.closed);
  EXPECT_TRUE(c.manifold);
  EXPECT_TRUE(c.consistently_oriented);
  EXPECT_EQ(c.unused_vertices, 0);
  EXPECT_EQ(c.degenerate_faces, 0);
}

TEST_P(BuiltinModel, SampledBodiesAreSoundAndOrdered) {
  const auto m = model(GetParam());
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  for (int sample = 0; sample < 25; ++sample) {
    Eigen::VectorXd beta(m->shape_count());
    for (auto& b : beta) b = sample == 0 ? 0.0 : 1.5 * normal(rng);
    const Vertices v = m->rest_vertices(beta);
    ASSERT_TRUE(v.allFinite());
    EXPECT_NEAR(v.col(1).minCoeff(), 0.0, 0.02) << "feet stay near the floor";
    EXPECT_GT(signed_volume(v, m->faces()), 0.02);
    const double ankle = height_of(*m, v, "lateral_malleolus_height"), knee = height_of(*m, v, "knee_height"),
                 crotch = height_of(*m, v, "crotch_height"), waist = height_of(*m, v, "waist_height"),
                 chest = height_of(*m, v, "chest_height"), acromion = height_of(*m, v, "acromial_height"),
                 stature = height_of(*m, v, "stature");
    EXPECT_LT(ankle, knee);
    EXPECT_LT(knee, crotch);
    EXPECT_LT(crotch, waist);
    EXPECT_LT(waist, chest);
    EXPECT_LT(chest, acromion);
    EXPECT_LT(acromion, stature);
    EXPECT_GT(stature, 1.2);
    EXPECT_LT(stature, 2.2);
  }
}

TEST_P(BuiltinModel, LandmarksAreMirrorSymmetric) {
  const auto m = model(GetParam());
  const Vertices v = m->rest_vertices(Eigen::VectorXd::Zero(m->shape_count()));
  int pairs = 0;
  for (const auto& [name, index] : m->data().landmarks) {
    const auto pos = name.rfind("_left");
    if (pos == std::string::npos || pos + 5 != name.size()) continue;
    const std::string right = name.substr(0, pos) + "_right";
    ASSERT_TRUE(m->data().landmarks.count(right)) << name;
    const Eigen::RowVector3d l = v.row(index), r = v.row(m->landmark(right));
    EXPECT_GT(l.x(), 0) << name << " is on the body's left (+X)";
    EXPECT_NEAR(l.x(), -r.x(), 0.005) << name;
    EXPECT_NEAR(l.y(), r.y(), 0.005) << name;
    EXPECT_NEAR(l.z(), r.z(), 0.005) << name;
    ++pairs;
  }
  EXPECT_GE(pairs, 10);
}

TEST_P(BuiltinModel, JointsAreInsideTheBodyAndOrdered) {
  const auto m = model(GetParam());
  const Vertices v = m->rest_vertices(Eigen::VectorXd::Zero(m->shape_count()));
  const Eigen::MatrixX3d j = m->joints(v);
  const Eigen::RowVector3d lo = v.colwise().minCoeff(), hi = v.colwise().maxCoeff();
  for (int i = 0; i < m->joint_count(); ++i)
    for (int c = 0; c < 3; ++c) {
      EXPECT_GT(j(i, c), lo(c)) << m->data().joint_names[i];
      EXPECT_LT(j(i, c), hi(c)) << m->data().joint_names[i];
    }
  auto y = [&](const char* name) {
    const auto& names = m->data().joint_names;
    return j(std::find(names.begin(), names.end(), name) - names.begin(), 1);
  };
  EXPECT_LT(y("left_ankle"), y("left_knee"));
  EXPECT_LT(y("left_knee"), y("left_hip"));
  EXPECT_LT(y("pelvis"), y("spine1"));
  EXPECT_LT(y("spine3"), y("neck"));
  EXPECT_LT(y("neck"), y("head"));
}

TEST_P(BuiltinModel, PresetRegressorsReproduceTheirInputs) {
  // Table 1 of the paper: inputs are reproduced (0.00 cm; weight within a fraction of a kg).
  const auto m = model(GetParam());
  AvatarBuilder builder(m);
  const bool male = GetParam() == Sex::Male;
  AvatarRequest req;
  req.measurements = measurements_from_edge({{"stature", male ? 178.0 : 164.0},
                                             {"weight", male ? 84.0 : 66.0},
                                             {"span", male ? 182.0 : 166.0},
                                             {"crotch_height", male ? 85.0 : 78.0},
                                             {"hip_breadth", male ? 34.5 : 35.5},
                                             {"arm_length", male ? 60.0 : 55.0}});
  for (const std::string preset : {"R2", "R4", "R5"}) {
    req.regressor = preset;
    const Avatar a = builder.build(req);
    for (const auto& input : a.inputs) {
      const double tol = input == "weight" ? 0.6 : 0.002;  // kg, m
      EXPECT_NEAR(a.achieved.at(input), req.measurements.at(input), tol) << preset << " " << input;
    }
    EXPECT_NE(a.plausibility.overall, Verdict::Implausible) << preset;
  }
}

TEST_P(BuiltinModel, CornerDesignMatchesMeasuringEachCornerBody) {
  // The design takes shortcuts (Gray-code updates, sections through a band of faces); every
  // row must still equal measuring that corner's body from scratch.
  const auto m = model(GetParam());
  const std::vector<std::string> names = {"stature", "span", "crotch_height", "hip_breadth", "arm_length", "weight"};
  const CornerDesign d = build_corner_design(*m, names);
  ASSERT_EQ(d.betas.rows(), 1024);
  for (Eigen::Index r : {0, 1, 63, 64, 500, 777, 1023}) {
    const Vertices v = m->rest_vertices(d.betas.row(r).transpose());
    for (size_t j = 0; j < names.size(); ++j) {
      const double direct = names[j] == "weight" ? std::cbrt(signed_volume(v, m->faces()))
                                                 : measure(*m, *m->find_measurement(names[j]), v);
      EXPECT_NEAR(d.features(r, static_cast<Eigen::Index>(j)), direct, 1e-6) << "row " << r << " " << names[j];
    }
  }
}

TEST_P(BuiltinModel, BendingAnElbowMovesOnlyTheForearm) {
  const auto m = model(GetParam());
  const Vertices rest = m->rest_vertices(Eigen::VectorXd::Zero(m->shape_count()));
  Pose p = zero_pose(*m);
  p.row(18) << 0, -M_PI / 2, 0;  // left elbow: forearm swings forward
  const Vertices posed = pose_vertices(*m, rest, p);
  ASSERT_TRUE(posed.allFinite());
  const Eigen::MatrixX3d joints = m->joints(rest);
  const double elbow_x = joints(18, 0);
  double max_move = 0, leg_move = 0;
  for (Eigen::Index i = 0; i < rest.rows(); ++i) {
    const double d = (posed.row(i) - rest.row(i)).norm();
    max_move = std::max(max_move, d);
    if (rest(i, 1) < joints(0, 1)) leg_move = std::max(leg_move, d);  // below the pelvis
    if (rest(i, 0) < elbow_x - 0.12) {
      EXPECT_LT(d, 1e-6) << "vertex " << i << " far from the elbow moved";
    }
  }
  EXPECT_GT(max_move, 0.2);   // the hand swings round
  EXPECT_LT(max_move, 0.8);   // bounded by the forearm + hand length × √2
  EXPECT_LT(leg_move, 1e-9);
}

#ifdef CALIPER_HAVE_ASSIMP
TEST_P(BuiltinModel, GlbReadsBackInAssimpWithTheSameCounts) {
  const auto m = model(GetParam());
  const Vertices rest = m->rest_vertices(Eigen::VectorXd::Constant(m->shape_count(), 0.5));
  const std::string bytes = write_glb(*m, rest);
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(), aiProcess_ValidateDataStructure, "glb");
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  ASSERT_EQ(scene->mNumMeshes, 1u);
  const aiMesh* mesh = scene->mMeshes[0];
  // One vertex per (vertex, UV) pair the faces use: the model's, plus copies along UV seams.
  std::set<std::pair<int, int>> pairs;
  for (Eigen::Index f = 0; f < m->faces().rows(); ++f)
    for (int c = 0; c < 3; ++c) pairs.insert({m->faces()(f, c), m->data().uv_faces(f, c)});
  ASSERT_TRUE(m->has_uvs());
  EXPECT_EQ(static_cast<int>(mesh->mNumVertices), static_cast<int>(pairs.size()));
  EXPECT_GT(static_cast<int>(mesh->mNumVertices), m->vertex_count());
  EXPECT_LT(static_cast<int>(mesh->mNumVertices), m->vertex_count() * 11 / 10);
  EXPECT_TRUE(mesh->HasTextureCoords(0));
  // Positions are the unsplit ones: the model's vertices first, in order.
  for (int v = 0; v < m->vertex_count(); v += 97)
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(mesh->mVertices[v][c], rest(v, c), 1e-6);
  EXPECT_EQ(static_cast<int>(mesh->mNumFaces), m->face_count());
  EXPECT_EQ(static_cast<int>(mesh->mNumBones), m->joint_count() + 1);  // and the root bone
  // Every vertex's weights sum to 1 across the bones.
  std::vector<double> sums(mesh->mNumVertices, 0.0);
  for (unsigned b = 0; b < mesh->mNumBones; ++b)
    for (unsigned w = 0; w < mesh->mBones[b]->mNumWeights; ++w)
      sums[mesh->mBones[b]->mWeights[w].mVertexId] += mesh->mBones[b]->mWeights[w].mWeight;
  for (double s : sums) ASSERT_NEAR(s, 1.0, 1e-5);
}

// The FBX of the real body, read back by Assimp: every triangle, every joint and the root bone,
// weights summing to 1, the avatar's height (in the file's centimetres).
TEST_P(BuiltinModel, FbxReadsBackInAssimpWithTheSameCounts) {
  const auto m = model(GetParam());
  const Vertices rest = m->rest_vertices(Eigen::VectorXd::Constant(m->shape_count(), 0.5));
  const std::string bytes = write_fbx(*m, rest);
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFileFromMemory(bytes.data(), bytes.size(),
                                                     aiProcess_ValidateDataStructure | aiProcess_JoinIdenticalVertices, "fbx");
  ASSERT_NE(scene, nullptr) << importer.GetErrorString();
  ASSERT_EQ(scene->mNumMeshes, 1u);
  const aiMesh* mesh = scene->mMeshes[0];
  EXPECT_EQ(static_cast<int>(mesh->mNumFaces), m->face_count());
  EXPECT_GE(static_cast<int>(mesh->mNumVertices), m->vertex_count());  // split along UV seams only
  EXPECT_LT(static_cast<int>(mesh->mNumVertices), m->vertex_count() * 11 / 10);
  EXPECT_TRUE(mesh->HasTextureCoords(0));
  EXPECT_EQ(static_cast<int>(mesh->mNumBones), m->joint_count() + 1);
  double lo = 1e9, hi = -1e9;
  for (unsigned v = 0; v < mesh->mNumVertices; ++v) lo = std::min<double>(lo, mesh->mVertices[v].y), hi = std::max<double>(hi, mesh->mVertices[v].y);
  EXPECT_NEAR(hi - lo, 100.0 * (rest.col(1).maxCoeff() - rest.col(1).minCoeff()), 1e-3);
  std::vector<double> sums(mesh->mNumVertices, 0.0);
  for (unsigned b = 0; b < mesh->mNumBones; ++b)
    for (unsigned w = 0; w < mesh->mBones[b]->mNumWeights; ++w)
      sums[mesh->mBones[b]->mWeights[w].mVertexId] += mesh->mBones[b]->mWeights[w].mWeight;
  for (double s : sums) ASSERT_NEAR(s, 1.0, 1e-5);
}
#endif

// A regressor reproduces its inputs inside the population; outside it, or when a given value is
// not one of its inputs, the avatar says so instead of being silently wrong.
TEST_P(BuiltinModel, AvatarsSayWhatTheyDidNotReproduce) {
  AvatarBuilder builder(model(GetParam()));
  AvatarRequest ordinary;
  ordinary.measurements = measurements_from_edge({{"stature", 170}, {"weight", 68}});
  const Avatar plain = builder.build(ordinary);
  EXPECT_TRUE(plain.warnings.empty()) << plain.warnings[0];
  // The default estimator reproduces values nobody said were noisy.
  EXPECT_NEAR(plain.achieved.at("stature"), 1.70, 1e-3);
  EXPECT_NEAR(plain.achieved.at("weight"), 68, 0.1);
  auto mentions = [](const Avatar& a, const std::string& what) {
    for (const auto& w : a.warnings)
      if (w.find(what) != std::string::npos) return true;
    return false;
  };
  AvatarRequest with_span = ordinary;
  with_span.regressor = "R2";
  with_span.measurements = measurements_from_edge({{"stature", 170}, {"weight", 68}, {"span", 255}});
  const Avatar a = builder.build(with_span);
  EXPECT_EQ(a.regressor, "R2");
  EXPECT_TRUE(mentions(a, "span was given but R2 does not use it")) << (a.warnings.empty() ? "" : a.warnings[0]);
  AvatarRequest absurd = ordinary;
  absurd.measurements = measurements_from_edge({{"stature", 60}, {"weight", 290}});
  absurd.regressor = "R2";
  // The paper's R2 extrapolates linearly: the body is either refused (a section misses it) or
  // built with a warning; never silently.
  try {
    const Avatar r2 = builder.build(absurd);
    EXPECT_TRUE(mentions(r2, "weight: the body reaches")) << (r2.warnings.empty() ? "" : r2.warnings[0]);
    EXPECT_EQ(r2.plausibility.overall, Verdict::Implausible);
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("does not cut the body"), std::string::npos) << e.what();
  }
  // The default gives the closest body inside the population instead, and says so.
  absurd.regressor = "auto";
  const Avatar best = builder.build(absurd);
  EXPECT_TRUE(mentions(best, "outside the population")) << (best.warnings.empty() ? "" : best.warnings[0]);
  EXPECT_GT(best.noise_widened, 1);
  EXPECT_NE(best.plausibility.overall, Verdict::Implausible);
  EXPECT_GT(best.achieved.at("stature"), 1.2);
  EXPECT_FALSE(best.plausibility.drivers.empty());
}

INSTANTIATE_TEST_SUITE_P(Sexes, BuiltinModel, ::testing::Values(Sex::Female, Sex::Male, Sex::Neutral),
                         [](const auto& info) { return std::string(to_string(info.param)); });
