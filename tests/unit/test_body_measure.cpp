// Body model, measurements, posing and the paper's regressors on a toy model whose answers are
// known exactly (every coordinate is linear in β).
#include <gtest/gtest.h>

#include <array>

#include <nlohmann/json.hpp>

#include "fixtures.h"

using namespace caliper;

TEST(BodyModel, RestVerticesAreTemplatePlusDirections) {
  const BodyModel m = test::toy_model();
  Eigen::VectorXd beta(2);
  beta << 1.0, 0.0;
  const Vertices v = m.rest_vertices(beta);
  const int top = m.landmark("vertex");
  EXPECT_NEAR(v(top, 1), 1.7 + 0.10, 1e-7);  // S·β in single precision
  EXPECT_NEAR(m.rest_vertices(Eigen::VectorXd())(top, 1), 1.7, 1e-12);  // shorter β = zeros
}

// gᵀS is how a function of the vertices changes with β: the toy model's top vertex rises 0.10
// per unit of β₀, not at all with β₁ and 0.05 with β₂ (fixtures.h), so the gradient of its
// height is (0.10, 0, 0.05).
TEST(BodyModel, ShapeGradientIsTheVertexGradientThroughTheDirections) {
  const BodyModel m = test::toy_model();
  Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * m.vertex_count());
  g(3 * m.landmark("vertex") + 1) = 1.0;  // ∂(top's height)/∂v
  const Eigen::RowVectorXd along = m.shape_gradient(g);
  ASSERT_EQ(along.size(), m.shape_count());
  EXPECT_NEAR(along(0), 0.10, 1e-7);
  EXPECT_NEAR(along(1), 0.0, 1e-7);
  EXPECT_NEAR(along(2), 0.05, 1e-7);
  // Against the double-precision product on a dense gradient.
  const Eigen::VectorXd dense = Eigen::VectorXd::LinSpaced(3 * m.vertex_count(), -1.0, 1.0);
  const Eigen::RowVectorXd exact = dense.transpose() * m.data().shape_directions;
  EXPECT_LT((m.shape_gradient(dense) - exact).cwiseAbs().maxCoeff(), 1e-6 * (1 + exact.cwiseAbs().maxCoeff()));
  EXPECT_THROW(m.shape_gradient(Eigen::VectorXd::Zero(4)), Error);
}

// The toy prism's directions are linear maps: β scales its height by 1 + (0.10 β₀ + 0.05 β₂)/1.7
// and its radius by 1 + (0.02 β₁ − 0.01 β₂)/0.15 (fixtures.h), so its volume is V(0) times the
// height's factor times the radius's squared: a cubic with every degree and cross term.
TEST(VolumePolynomial, IsTheToyPrismsVolumeExactly) {
  const BodyModel m = test::toy_model();
  const VolumePolynomial poly(m);
  ASSERT_EQ(poly.shape_count(), 3);
  const double v0 = signed_volume(m.data().template_vertices, m.faces());
  ASSERT_GT(v0, 0);
  auto expected = [&](const Eigen::Vector3d& b, Eigen::RowVector3d& gradient) {
    const double h = 1 + (0.10 * b(0) + 0.05 * b(2)) / 1.7, r = 1 + (0.02 * b(1) - 0.01 * b(2)) / 0.15;
    const Eigen::RowVector3d dh(0.10 / 1.7, 0, 0.05 / 1.7), dr(0, 0.02 / 0.15, -0.01 / 0.15);
    gradient = v0 * (dh * r * r + 2 * h * r * dr);
    return v0 * h * r * r;
  };
  for (const Eigen::Vector3d& b : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, -2, 0),
                                  Eigen::Vector3d(0, 0, 3), Eigen::Vector3d(2.5, -1.5, 3.0), Eigen::Vector3d(-3, 3, -2)}) {
    Eigen::RowVector3d want_gradient;
    const double want = expected(b, want_gradient);
    Eigen::RowVectorXd gradient;
    EXPECT_NEAR(poly.value(b, &gradient), want, 1e-12 * v0) << b.transpose();
    ASSERT_EQ(gradient.size(), 3);
    EXPECT_LT((gradient - want_gradient).cwiseAbs().maxCoeff(), 1e-12 * v0) << b.transpose();
  }
  Eigen::RowVector3d unused;
  EXPECT_NEAR(poly.value(Eigen::VectorXd::Constant(1, 2.0)), expected(Eigen::Vector3d(2, 0, 0), unused), 1e-12 * v0);
  EXPECT_THROW(poly.value(Eigen::VectorXd::Zero(4)), Error);
  EXPECT_THROW(poly.value(Eigen::VectorXd::Constant(2, std::nan(""))), Error);
}

TEST(BodyModel, RejectsBadBeta) {
  const BodyModel m = test::toy_model();
  EXPECT_THROW(m.rest_vertices(Eigen::VectorXd::Zero(4)), Error);
  Eigen::VectorXd nan = Eigen::VectorXd::Zero(2);
  nan(1) = std::nan("");
  EXPECT_THROW(m.rest_vertices(nan), Error);
}

TEST(BodyModel, ValidatesInconsistentData) {
  BodyModelData d = test::toy_model().data();
  d.faces(0, 0) = 100000;
  try {
    BodyModel bad(d);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "faces");
  }
  BodyModelData d2 = test::toy_model().data();
  d2.parents[5] = 7;  // parent after child
  EXPECT_THROW(BodyModel{d2}, Error);
  BodyModelData d3 = test::toy_model().data();
  d3.measurements.push_back({"x", MeasurementKind::Height, {"nowhere"}, Axis::Y, ""});
  EXPECT_THROW(BodyModel{d3}, Error);
}

TEST(Measure, ToyModelExactValues) {
  const BodyModel m = test::toy_model(24, 9);
  const Vertices v = m.rest_vertices(Eigen::VectorXd::Zero(3));
  auto all = measure_all(m, v);
  EXPECT_NEAR(all["stature"], 1.7, 1e-12);
  EXPECT_NEAR(all["crotch_height"], 1.7 * 2 / 8, 1e-12);
  EXPECT_NEAR(all["waist_circumference"], 2 * 24 * 0.15 * std::sin(M_PI / 24), 1e-9);
  EXPECT_NEAR(all["waist_breadth"], 0.30, 1e-9);  // 24-gon has vertices at 0° and 180°
  EXPECT_NEAR(all["waist_depth"], 0.30, 1e-9);    // and at 90°, 270°
  const double area = 0.5 * 24 * 0.15 * 0.15 * std::sin(2 * M_PI / 24);
  EXPECT_NEAR(all["weight"], 1000 * area * 1.7, 1e-9);
}

// A chest wider at the back than across its front (the latissimus behind the arms): the toy
// prism's rings reshaped to a hexagon whose front corners stand 6 cm apart at z = +2 cm, its
// sides at ±4 cm at z = −0.5 cm and its back corners 10 cm apart at z = −2 cm. The section's
// depth is 4 cm, its middle z = 0; the front half's widest points are where the side edges cross
// z = 0, a fifth of the way from (±4, −0.5) to (±3, 2): x = ±3.8 cm.
TEST(Measure, FrontBreadthIsTheFrontHalfsWidth) {
  BodyModelData d = test::toy_model(6, 9).data();
  const std::array<Eigen::Vector2d, 6> corner = {{{0.04, -0.005}, {0.03, 0.02}, {-0.03, 0.02},
                                                  {-0.04, -0.005}, {-0.05, -0.02}, {0.05, -0.02}}};
  for (int ring = 0; ring < 9; ++ring)
    for (int k = 0; k < 6; ++k) {
      d.template_vertices(ring * 6 + k, 0) = corner[static_cast<size_t>(k)].x();
      d.template_vertices(ring * 6 + k, 2) = corner[static_cast<size_t>(k)].y();
    }
  d.measurements = {{"chest_breadth", MeasurementKind::FrontBreadth, {"waist_side"}, Axis::Y, "front half"},
                    {"waist_breadth", MeasurementKind::Breadth, {"waist_side"}, Axis::Y, "whole"}};
  const BodyModel m(std::move(d));
  auto all = measure_all(m, m.data().template_vertices);
  EXPECT_NEAR(all["chest_breadth"], 0.076, 1e-12);
  EXPECT_NEAR(all["waist_breadth"], 0.10, 1e-12);
  // Its gradient against central differences, moving each corner of the measured ring across
  // (x) and front to back (z): the crossing points move with both ends of their edges and, through
  // the middle of the depth, with the front and back corners. Without ties for the front and back
  // (there the derivative is one-sided): the front-left corner 1 mm further back and the
  // back-right 1 mm further back, so the middle is z = −0.5 mm and the crossings lie at
  // x = 3.82 and −3.8125 cm.
  const int ring = 4;
  const MeasurementDefinition& def = m.data().measurements[0];
  auto check_gradient = [&](const Vertices& v, const std::string& shape) {
    const MeasurementGradient g = measure_with_gradient(m, def, v, m.faces());
    EXPECT_NEAR(g.value, measure(m, def, v), 1e-15) << shape;
    constexpr double kStep = 1e-6;
    for (int k = 0; k < 6; ++k)
      for (int axis : {0, 2}) {
        const int vertex = ring * 6 + k;
        Vertices up = v, down = v;
        up(vertex, axis) += kStep;
        down(vertex, axis) -= kStep;
        const double numeric = (measure(m, def, up) - measure(m, def, down)) / (2 * kStep);
        double predicted = 0;
        for (const auto& term : g.terms)
          if (term.vertex == vertex) predicted += term.d(axis);
        EXPECT_NEAR(predicted, numeric, 1e-6) << shape << ", corner " << k << (axis == 0 ? " x" : " z");
      }
  };
  Vertices v = m.data().template_vertices;
  v(ring * 6 + 2, 2) = 0.019;
  v(ring * 6 + 5, 2) = -0.021;
  EXPECT_NEAR(measure(m, def, v), 0.0382 + 0.038125, 1e-12);
  check_gradient(v, "crossings at both ends");
  // The right side's corner moved out to (5.5, 0.4) cm, in front of the middle: it is the front
  // half's right end itself (the edge from the back corner crosses the middle at x = 5.41 cm).
  v(ring * 6 + 0, 0) = 0.055;
  v(ring * 6 + 0, 2) = 0.004;
  EXPECT_NEAR(measure(m, def, v), 0.055 + 0.038125, 1e-12);
  check_gradient(v, "a corner at the right end");
  // Only horizontal sections have a front half: a model that says otherwise is refused, and so is
  // measuring with such a definition.
  BodyModelData tilted = m.data();
  tilted.measurements[0].plane_normal = Axis::X;
  EXPECT_THROW(BodyModel{tilted}, Error);
  EXPECT_THROW(measure(m, tilted.measurements[0], m.data().template_vertices), Error);
}

TEST(Measure, BareMeshNeedsClosedSurface) {
  Mesh cube = test::unit_cube();
  const MeshMeasurements mm = measure_mesh(cube, {1000, 0});
  EXPECT_NEAR(mm.stature, 1.0, 1e-15);
  EXPECT_NEAR(mm.weight, 1000.0, 1e-9);
  cube.faces.conservativeResize(11, 3);
  EXPECT_THROW(measure_mesh(cube, {1000, 0}), Error);
}

TEST(Pose, ZeroPoseIsIdentity) {
  const BodyModel m = test::toy_model();
  const Vertices rest = m.rest_vertices(Eigen::VectorXd::Zero(3));
  const Vertices posed = pose_vertices(m, rest, zero_pose(m));
  EXPECT_LT((posed - rest).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Pose, RootRotationRotatesEverythingRigidly) {
  const BodyModel m = test::toy_model();
  const Vertices rest = m.rest_vertices(Eigen::VectorXd::Zero(3));
  Pose p = zero_pose(m);
  p.row(0) << 0, M_PI / 2, 0;  // quarter turn about +Y
  const Vertices posed = pose_vertices(m, rest, p);
  // Distances are preserved by a rigid motion.
  for (int i : {0, 5, 40, 100})
    EXPECT_NEAR((posed.row(i) - posed.row(i + 1)).norm(), (rest.row(i) - rest.row(i + 1)).norm(), 1e-12);
  EXPECT_GT((posed - rest).cwiseAbs().maxCoeff(), 0.01);
}

TEST(Pose, RejectsWrongShapeAndNaN) {
  const BodyModel m = test::toy_model();
  const Vertices rest = m.rest_vertices(Eigen::VectorXd::Zero(3));
  EXPECT_THROW(pose_vertices(m, rest, Pose::Zero(3, 3)), Error);
  Pose p = zero_pose(m);
  p(3, 1) = std::nan("");
  EXPECT_THROW(pose_vertices(m, rest, p), Error);
  EXPECT_THROW(a_pose(m, 200), Error);
}

TEST(Regressor, Presets) {
  EXPECT_EQ(preset_inputs("R5").size(), 5u);
  EXPECT_EQ(preset_inputs("R2"), (std::vector<std::string>{"stature", "weight"}));
  EXPECT_THROW(preset_inputs("R7"), Error);
}

TEST(Regressor, ReproducesLinearInputsExactly) {
  // Heights are exactly linear in β: the least-squares regressor over the corners inverts them.
  const BodyModel m = test::toy_model();
  const CornerDesign design = build_corner_design(m, {"stature", "crotch_height", "waist_breadth", "weight"});
  EXPECT_EQ(design.betas.rows(), 8);  // 2^3 corners
  Regressor r(design, {"stature", "waist_breadth"}, "custom");
  std::map<std::string, double> target = {{"stature", 1.76}, {"waist_breadth", 0.33}};
  const Vertices v = m.rest_vertices(r.predict(m, target));
  EXPECT_NEAR(measure(m, *m.find_measurement("stature"), v), 1.76, 1e-7);
  EXPECT_NEAR(measure(m, *m.find_measurement("waist_breadth"), v), 0.33, 1e-7);
}

TEST(Regressor, TrainingIsBitForBitReproducible) {
  const BodyModel m = test::toy_model();
  const CornerDesign a = build_corner_design(m, {"stature", "weight"});
  const CornerDesign b = build_corner_design(m, {"stature", "weight"});
  Regressor ra(a, {"stature", "weight"}, "R2"), rb(b, {"stature", "weight"}, "R2");
  EXPECT_EQ(std::memcmp(ra.coefficients().data(), rb.coefficients().data(), sizeof(double) * ra.coefficients().size()), 0);
  EXPECT_EQ(std::memcmp(ra.intercept().data(), rb.intercept().data(), sizeof(double) * ra.intercept().size()), 0);
}

TEST(Plausibility, BandsPerValueAndJointVerdict) {
  Eigen::VectorXd b = Eigen::VectorXd::Zero(10);
  EXPECT_EQ(judge_plausibility(b).overall, Verdict::Plausible);
  EXPECT_DOUBLE_EQ(judge_plausibility(b).tail_probability, 1.0);
  b(3) = 2.5;
  auto p = judge_plausibility(b);
  EXPECT_EQ(p.per_value[3], Verdict::Unusual);
  // One value at 2.5 SD: 79 % of χ²₁₀ lies beyond ‖β‖² = 6.25; one of ten normals beyond 2.5 SD
  // in 1 − (1 − 0.012419)¹⁰ = 11.73 % of people; doubled: an ordinary body.
  EXPECT_EQ(p.overall, Verdict::Plausible);
  EXPECT_NEAR(p.tail_probability, 2 * 0.11733, 1e-3);
  EXPECT_NE(p.explanation.find("shape 4"), std::string::npos);
  // One value at 3.3 SD: 1 − (1 − 0.000967)¹⁰ = 0.963 %, doubled 1.93 %: plausible but rare;
  // at 3.6 SD (0.318 % ×10, doubled 0.636 %): unusual; at 5 SD: implausible.
  b(3) = 3.3;
  EXPECT_EQ(judge_plausibility(b).overall, Verdict::Plausible);
  EXPECT_EQ(judge_plausibility(b).per_value[3], Verdict::Implausible);
  b(3) = 3.6;
  EXPECT_EQ(judge_plausibility(b).overall, Verdict::Unusual);
  b(3) = 5.0;
  EXPECT_EQ(judge_plausibility(b).overall, Verdict::Implausible);
  // Every value within 2 SD, but all ten at 1.9 SD together are far out (‖β‖² = 36.1, 0.008 %).
  const Eigen::VectorXd all = Eigen::VectorXd::Constant(10, 1.9);
  auto q = judge_plausibility(all);
  EXPECT_EQ(q.per_value[0], Verdict::Plausible);
  EXPECT_EQ(q.overall, Verdict::Implausible);
  EXPECT_NE(q.rarity.find("rarer than 1 in 1,000"), std::string::npos) << q.rarity;
}

// The χ² tail against values from statistical tables (k = 1: 3.841 → 5 %; k = 2: e^{−x/2};
// k = 10: 23.209 → 1 %, 29.588 → 0.1 %; k = 25: 44.314 → 1 %; k = 30: 50.892 → 1 %).
TEST(Plausibility, ChiSquareTailMatchesTables) {
  EXPECT_NEAR(chi_square_tail(1, 3.841), 0.05, 1e-4);
  EXPECT_NEAR(chi_square_tail(2, 3.0), std::exp(-1.5), 1e-12);
  EXPECT_NEAR(chi_square_tail(10, 23.209), 0.01, 1e-4);
  EXPECT_NEAR(chi_square_tail(10, 29.588), 0.001, 1e-5);
  EXPECT_NEAR(chi_square_tail(30, 50.892), 0.01, 1e-4);
  EXPECT_NEAR(chi_square_tail(25, 44.314), 0.01, 1e-4);
}

// A real → virtual map (paper §3.3): the avatar is built for the mapped (rest-pose) value, and
// the report compares what a person measures: achieved maps back through the same map.
TEST(Avatar, ReportGivesMappedMeasurementsAsAPersonMeasuresThem) {
  auto model = std::make_shared<const BodyModel>(test::toy_model());
  AvatarBuilder builder(model);
  AvatarRequest req;
  req.measurements = measurements_from_edge({{"height", 175}, {"weight", 120}});
  req.regressor = "R2";
  RealToVirtual maps;
  maps.set("stature", LinearMap{1.1, -0.1});  // rest pose = 1.1 · 175 cm − 10 cm = 182.5 cm
  req.maps = maps;
  const Avatar a = builder.build(req);
  EXPECT_NEAR(a.achieved.at("stature"), 1.825, 1e-6) << "the body is built for the rest-pose value";
  EXPECT_NEAR(as_measured(a, "stature", a.achieved.at("stature")), 1.75, 1e-6);
  EXPECT_TRUE(measured_differs_from_rest_pose(a, "stature"));
  EXPECT_FALSE(measured_differs_from_rest_pose(a, "weight"));
  const auto j = nlohmann::json::parse(avatar_report_json(*model, a));
  const auto& s = j["measurements"]["stature"];
  EXPECT_NEAR(s["requested_cm"].get<double>(), 175.0, 1e-9);
  EXPECT_NEAR(s["achieved_cm"].get<double>(), 175.0, 1e-3);
  EXPECT_NEAR(s["difference_cm"].get<double>(), 0.0, 1e-3);
  EXPECT_NEAR(s["rest_pose_cm"].get<double>(), 182.5, 1e-3);
  EXPECT_NEAR(s["rest_pose_target_cm"].get<double>(), 182.5, 1e-3);
  EXPECT_FALSE(j["measurements"]["weight"].contains("rest_pose_kg"));
  EXPECT_TRUE(j.contains("rest_pose_note"));
  // Without maps nothing differs and the report says nothing about a rest pose.
  req.apply_model_maps = false;
  const Avatar plain = builder.build(req);
  EXPECT_NEAR(plain.achieved.at("stature"), 1.75, 1e-6);
  const auto k = nlohmann::json::parse(avatar_report_json(*model, plain));
  EXPECT_FALSE(k["measurements"]["stature"].contains("rest_pose_cm"));
  EXPECT_FALSE(k.contains("rest_pose_note"));
}

TEST(Avatar, BuildsAndReportsRequestedBesideAchieved) {
  auto model = std::make_shared<const BodyModel>(test::toy_model());
  AvatarBuilder builder(model);
  AvatarRequest req;
  req.measurements = measurements_from_edge({{"height", 175}, {"weight", 120}});
  req.regressor = "R2";
  const Avatar a = builder.build(req);
  EXPECT_EQ(a.regressor, "R2");
  EXPECT_NEAR(a.achieved.at("stature"), 1.75, 1e-6);
  const auto j = nlohmann::json::parse(avatar_report_json(*model, a));
  EXPECT_EQ(j["regressor"], "R2");
  EXPECT_NEAR(j["measurements"]["stature"]["requested_cm"].get<double>(), 175.0, 1e-9);
  EXPECT_TRUE(j["measurements"]["weight"].contains("achieved_kg"));
  EXPECT_FALSE(j["measurements"]["crotch_height"].contains("requested_cm"));
  EXPECT_TRUE(j["plausibility"].contains("verdict"));
  EXPECT_TRUE(j["plausibility"].contains("rarity"));
  // The default, auto, is the noise-aware estimator over every value given.
  req.regressor = "auto";
  EXPECT_EQ(builder.build(req).regressor, "map");
  // R4 needs span and crotch height, which were not given.
  req.regressor = "R4";
  EXPECT_THROW(builder.build(req), Error);
}

TEST(Avatar, EdgeValuesAreChecked) {
  EXPECT_THROW(measurements_from_edge({{"stature", std::nan("")}}), Error);
  try {
    measurements_from_edge({{"stature", 1700}});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::OutOfRange);
    EXPECT_EQ(e.field(), "stature");
    EXPECT_NE(std::string(e.what()).find("[50, 250] cm"), std::string::npos);
  }
  EXPECT_THROW(measurements_from_edge({{"weight", -3}}), Error);
  EXPECT_THROW(measurements_from_edge({{"height", 170}, {"stature", 171}}), Error);
  EXPECT_THROW(measurements_from_edge({{"shoe_size", 42}}), Error);
  EXPECT_NEAR(measurements_from_edge({{"inseam", 80}}).at("crotch_height"), 0.80, 1e-15);
}
