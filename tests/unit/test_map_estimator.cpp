// The noise-aware MAP estimator: a closed-form linear-Gaussian case on the toy model,
// exactness on noise-free consistent inputs, reconciliation of contradictory inputs with a warning
// naming the culprit, uncertainty shrinking as measurements are added, and calibration of the
// predicted SDs on synthetic bodies. Tests over the built-in body use invariants only.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <thread>

#include "caliper/avatar.h"
#include "caliper/errors.h"
#include "caliper/avatar_report.h"
#include "caliper/io/model_files.h"
#include "caliper/measure/measure.h"
#include "caliper/random.h"
#include "caliper/regress/map_estimator.h"
#include "fixtures.h"

using namespace caliper;

namespace {

std::shared_ptr<const BodyModel> female() {
  static const auto model = std::make_shared<const BodyModel>(load_model("mannequin", Sex::Female));
  return model;
}

std::map<std::string, double> measure_named(const BodyModel& model, const Eigen::VectorXd& beta,
                                            const std::vector<std::string>& names) {
  return measure_some(model, names, model.rest_vertices(beta));
}

const std::vector<std::string> kR6 = {"stature", "weight", "span", "crotch_height", "hip_breadth", "arm_length"};

}  // namespace

// Toy model, stature only: stature = 1.7 + 0.10·β0 + 0.05·β2 exactly (the floor stays at y = 0),
// so the posterior is the textbook linear-Gaussian one with g = (0.10, 0, 0.05):
//   β̂ = g (y − 1.7) / (σ² + ‖g‖²),  Σ = I − g gᵀ / (σ² + ‖g‖²),  SD(stature) = σ‖g‖ / √(σ² + ‖g‖²).
TEST(MapEstimator, LinearGaussianCaseMatchesClosedForm) {
  const auto toy = std::make_shared<const BodyModel>(test::toy_model());
  MapEstimator estimator(toy);
  MapOptions opt;
  const double sigma = 0.02, y = 1.80;
  opt.noise_sd["stature"] = sigma;
  opt.gross_error_rate = 0;  // the pure Gaussian model
  const MapEstimate est = estimator.estimate({{"stature", y}}, opt);
  const Eigen::Vector3d g(0.10, 0.0, 0.05);
  const double s = sigma * sigma + g.squaredNorm();
  const Eigen::Vector3d beta = g * (y - 1.7) / s;
  ASSERT_EQ(est.beta.size(), 3);
  EXPECT_TRUE(est.converged);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(est.beta(i), beta(i), 1e-6) << i;
  const Eigen::Matrix3d cov = Eigen::Matrix3d::Identity() - g * g.transpose() / s;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(est.covariance(i, j), cov(i, j), 1e-6) << i << "," << j;
  EXPECT_NEAR(est.measurement_sd.at("stature"), sigma * g.norm() / std::sqrt(s), 1e-6);
  // One input: "the others" are the prior alone, which predicts 1.7 ± ‖g‖.
  const MapInputFit& fit = est.inputs.at("stature");
  EXPECT_NEAR(fit.expected, 1.7, 1e-6);
  EXPECT_NEAR(fit.expected_sd, g.norm(), 1e-6);
  EXPECT_NEAR(fit.z, (y - 1.7) / std::sqrt(s), 1e-5);
  EXPECT_NEAR(fit.fitted, 1.7 + g.dot(beta), 1e-6);
  // The top centre vertex moves only in y, exactly as stature does.
  ASSERT_EQ(est.vertex_sd.size(), toy->vertex_count());
  EXPECT_NEAR(est.vertex_sd(toy->landmark("vertex")), est.measurement_sd.at("stature"), 1e-6);
  // Vertices at the bottom centre do not move with β: no uncertainty.
  EXPECT_NEAR(est.vertex_sd(toy->vertex_count() - 2), 0.0, 1e-12);
}

TEST(MapEstimator, RejectsBadInput) {
  MapEstimator estimator(std::make_shared<const BodyModel>(test::toy_model()));
  try {
    estimator.estimate({{"chest_circumference", 0.9}});
    FAIL() << "a measurement the toy lacks must be refused";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Unsupported);
    EXPECT_EQ(e.field(), "chest_circumference");
  }
  try {
    estimator.estimate({{"stature", NAN}});
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
    EXPECT_EQ(e.field(), "stature");
  }
  MapOptions opt;
  opt.noise_sd["stature"] = 0;
  try {
    estimator.estimate({{"stature", 1.7}}, opt);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "stature");
  }
  EXPECT_THROW(estimator.estimate({}), Error);
  EXPECT_THROW(parse_noise_setting("sloppy"), Error);
  EXPECT_EQ(parse_noise_setting("Other"), NoiseSetting::Other);
}

TEST(MapEstimator, Table2DefaultsAreMaeTimesRootHalfPi) {
  const auto self = table2_sd(NoiseSetting::Self);
  EXPECT_NEAR(self.at("span"), 0.0201 * std::sqrt(M_PI / 2), 1e-12);
  EXPECT_NEAR(table2_sd(NoiseSetting::Other).at("hip_breadth"), 0.0065 * std::sqrt(M_PI / 2), 1e-12);
  EXPECT_TRUE(table2_sd(NoiseSetting::Exact).empty());
  const BodyModel& model = *female();
  EXPECT_NEAR(default_noise_sd(model, "stature", NoiseSetting::Self), self.at("stature"), 1e-12);
  EXPECT_LT(default_noise_sd(model, "stature", NoiseSetting::Exact), 1e-3);
  for (const auto& def : model.data().measurements)
    for (NoiseSetting s : {NoiseSetting::Exact, NoiseSetting::Self, NoiseSetting::Other})
      EXPECT_GT(default_noise_sd(model, def.name, s), 0) << def.name;
}

// Measurements of a known body β* with the "exact" noise floor: every measurement the model
// has pins all K shape values, so β* comes back; the inputs are reproduced to a fraction of a mm.
TEST(MapEstimator, NoiseFreeInputsGiveTheBodyBack) {
  const auto model = female();
  Eigen::VectorXd truth(model->shape_count());
  NormalGenerator rng(7);
  for (auto& b : truth) b = 0.8 * rng.normal();
  std::vector<std::string> all;
  for (const auto& d : model->data().measurements) all.push_back(d.name);
  const auto values = measure_named(*model, truth, all);
  MapOptions opt;
  opt.noise = NoiseSetting::Exact;
  opt.vertex_uncertainty = false;
  const MapEstimate est = MapEstimator(model).estimate(values, opt);
  EXPECT_TRUE(est.converged);
  EXPECT_LT((est.beta - truth).cwiseAbs().maxCoeff(), 1e-3) << est.beta.transpose() << "\nvs " << truth.transpose();
  for (const auto& [name, fit] : est.inputs)
    EXPECT_NEAR(fit.fitted, fit.value, name == "weight" ? 0.02 : 2e-4) << name;
  EXPECT_TRUE(est.warnings.empty()) << est.warnings.front();
}

// Above 64 shape directions the estimator weighs the mesh at every step instead of the volume
// polynomial (MapEstimator::volume). The toy model with 67 more directions that move nothing
// must give the toy's own estimate on both paths.
TEST(MapEstimator, ManyShapeDirectionsWeighTheMesh) {
  const auto toy = std::make_shared<const BodyModel>(test::toy_model());
  BodyModelData wide_data = toy->data();
  wide_data.shape_directions.conservativeResize(Eigen::NoChange, 70);
  wide_data.shape_directions.rightCols(67).setZero();
  const auto wide = std::make_shared<const BodyModel>(std::move(wide_data));
  Eigen::VectorXd truth(3);
  truth << 0.8, -1.1, 0.4;
  const auto values = measure_named(*toy, truth, {"stature", "weight", "waist_circumference"});
  MapOptions opt;
  opt.noise = NoiseSetting::Exact;
  opt.vertex_uncertainty = false;
  const MapEstimate by_polynomial = MapEstimator(toy).estimate(values, opt);
  const MapEstimate by_mesh = MapEstimator(wide).estimate(values, opt);
  ASSERT_EQ(by_mesh.beta.size(), 70);
  // The same body to within the solver's own stopping rule (a step under 1e-3 SD).
  EXPECT_LT((by_mesh.beta.head(3) - by_polynomial.beta).cwiseAbs().maxCoeff(), 2e-3)
      << by_mesh.beta.head(3).transpose() << " vs " << by_polynomial.beta.transpose();
  EXPECT_LT(by_mesh.beta.tail(67).cwiseAbs().maxCoeff(), 1e-9);
  for (const auto& [name, fit] : by_mesh.inputs)
    EXPECT_NEAR(fit.fitted, values.at(name), name == "weight" ? 0.02 : 2e-4) << name;
  EXPECT_NEAR(by_mesh.inputs.at("weight").fitted, by_polynomial.inputs.at("weight").fitted, 1e-3);
}

// What a user gets by default (auto, no noise stated): the given values of twenty people drawn
// from the population come back to within 0.1 cm and 0.1 kg, whatever subset was given.
TEST(MapEstimator, DefaultEstimatorReproducesGivenValues) {
  const auto model = female();
  AvatarBuilder builder(model);
  NormalGenerator rng(11);
  const std::vector<std::vector<std::string>> subsets = {
      {"stature", "weight"}, kR6, {"stature", "weight", "span", "hip_breadth"}, {"stature", "chest_circumference", "waist_circumference"}};
  for (int person = 0; person < 20; ++person) {
    Eigen::VectorXd truth(model->shape_count());
    for (auto& b : truth) b = rng.normal();
    const auto& subset = subsets[static_cast<size_t>(person) % subsets.size()];
    AvatarRequest req;  // defaults: regressor auto, noise exact
    req.measurements = measure_named(*model, truth, subset);
    req.apply_model_maps = false;
    const Avatar a = builder.build(req);
    EXPECT_EQ(a.noise_widened, 1) << "person " << person << " was moved inside the population";
    for (const auto& name : subset)
      EXPECT_NEAR(a.achieved.at(name), req.measurements.at(name), name == "weight" ? 0.1 : 1e-3) << name << ", person " << person;
  }
}

// The paper's six inputs from a known body, exact: fewer inputs than shape values, so β differs
// from β*, but every input is reproduced at least as well as R6 reproduces its own.
TEST(MapEstimator, NoiseFreeR6InputsReproducedLikeTheRegressor) {
  const auto model = female();
  Eigen::VectorXd truth = Eigen::VectorXd::Zero(model->shape_count());
  truth(0) = 1.2;
  truth(1) = -0.7;
  truth(3) = 0.9;
  const auto values = measure_named(*model, truth, kR6);
  AvatarBuilder builder(model);
  AvatarRequest req;
  req.measurements = values;
  req.apply_model_maps = false;
  req.regressor = "map";
  req.noise = "exact";
  req.measure_only = kR6;
  const Avatar map = builder.build(req);
  req.regressor = "R6";
  const Avatar r6 = builder.build(req);
  for (const auto& name : kR6) {
    const double tol = name == "weight" ? 0.05 : 5e-4;
    const double map_error = std::abs(map.achieved.at(name) - values.at(name));
    EXPECT_LT(map_error, tol) << name;
    EXPECT_LE(map_error, std::abs(r6.achieved.at(name) - values.at(name)) + tol / 5) << name;
  }
  EXPECT_EQ(map.regressor, "map");
  EXPECT_EQ(map.noise, "exact");
  EXPECT_EQ(map.inputs.size(), kR6.size());
}

// A span 30 cm longer than this stature's body allows: R4 has to honour it and leaves the
// population; map keeps a plausible body and names span as the culprit.
TEST(MapEstimator, ContradictorySpanIsReconciledAndNamed) {
  const auto model = female();
  const Eigen::VectorXd mean = Eigen::VectorXd::Zero(model->shape_count());
  auto values = measure_named(*model, mean, {"stature", "weight", "span", "crotch_height"});
  values["span"] += 0.30;
  AvatarBuilder builder(model);
  AvatarRequest req;
  req.measurements = values;
  req.apply_model_maps = false;
  req.noise = "self";  // the default regressor, auto, with self-measured values
  const Avatar map = builder.build(req);
  EXPECT_EQ(map.regressor, "map");
  EXPECT_GT(map.input_fits.at("span").effective_sd, 2 * map.input_fits.at("span").noise_sd) << "not down-weighted";
  EXPECT_NE(map.plausibility.overall, Verdict::Implausible) << map.plausibility.explanation;
  ASSERT_FALSE(map.warnings.empty());
  EXPECT_EQ(map.warnings[0].rfind("span is ", 0), 0u) << map.warnings[0];
  EXPECT_NE(map.warnings[0].find("longer"), std::string::npos) << map.warnings[0];
  EXPECT_NE(map.warnings[0].find("than the other measurements and the body model's population allow"), std::string::npos)
      << map.warnings[0];
  EXPECT_GT(map.input_fits.at("span").z, 3.0);
  // The other inputs are the consistent ones: none of them is blamed.
  for (const auto& w : map.warnings) EXPECT_EQ(w.find("stature is"), std::string::npos) << w;
  // Reconciled: the avatar's span lies between what the rest predicts and what was given.
  const double achieved = map.achieved.at("span");
  EXPECT_LT(achieved, values.at("span") - 0.10);
  EXPECT_GT(achieved, values.at("span") - 0.30 - 0.02);
  req.regressor = "R4";
  const Avatar r4 = builder.build(req);
  EXPECT_EQ(r4.plausibility.overall, Verdict::Implausible) << "the contradiction is not strong enough to test with";
  // The report carries the warning and the per-measurement uncertainty.
  const auto report = nlohmann::json::parse(avatar_report_json(*model, map));
  ASSERT_EQ(report.at("warnings").size(), map.warnings.size());
  EXPECT_GT(report.at("measurements").at("span").at("uncertainty_cm").get<double>(), 0.0);
  EXPECT_GT(report.at("measurements").at("weight").at("uncertainty_kg").get<double>(), 0.0);
  EXPECT_EQ(report.at("uncertainty").at("noise"), "self");
}

// With only stature and weight given, a warning about the weight names the stature it was weighed
// against: "than the other measurements" read as if more had been given.
TEST(MapEstimator, WarningNamesTheOnlyOtherMeasurement) {
  const auto model = female();
  auto values = measure_named(*model, Eigen::VectorXd::Zero(model->shape_count()), {"stature", "weight"});
  values["weight"] *= 1.6;
  AvatarBuilder builder(model);
  AvatarRequest req;
  req.measurements = values;
  req.apply_model_maps = false;
  req.noise = "self";
  const Avatar a = builder.build(req);
  ASSERT_FALSE(a.warnings.empty());
  EXPECT_EQ(a.warnings[0].rfind("weight is ", 0), 0u) << a.warnings[0];
  EXPECT_NE(a.warnings[0].find("than stature and the body model's population allow"), std::string::npos) << a.warnings[0];
  const auto drivers = describe_drivers(*model, a.input_fits, nullptr);
  bool named = false;
  for (const auto& d : drivers) {
    EXPECT_EQ(d.find("other measurements"), std::string::npos) << d;
    named = named || d.find("than stature suggests") != std::string::npos;
  }
  EXPECT_TRUE(named) << "no driver compares the weight with the stature";
  // Two others are named too; three or more are "the other measurements" (the span test above).
  req.measurements["span"] = measure_named(*model, Eigen::VectorXd::Zero(model->shape_count()), {"span"}).at("span");
  const Avatar b = builder.build(req);
  ASSERT_FALSE(b.warnings.empty());
  EXPECT_EQ(b.warnings[0].rfind("weight is ", 0), 0u) << b.warnings[0];
  EXPECT_NE(b.warnings[0].find("than span, stature and the body model's population allow"), std::string::npos) << b.warnings[0];
}

TEST(MapEstimator, ConsistentNoisyInputsGiveNoWarning) {
  const auto model = female();
  Eigen::VectorXd truth = Eigen::VectorXd::Zero(model->shape_count());
  truth(0) = -0.5;
  truth(2) = 0.6;
  const MapEstimate est = MapEstimator(model).estimate(measure_named(*model, truth, kR6));
  EXPECT_TRUE(est.warnings.empty()) << est.warnings.front();
  for (const auto& [name, fit] : est.inputs) EXPECT_LT(std::abs(fit.z), 1.0) << name;
}

// Adding measurements can only add information: in the linearised posterior every SD shrinks
// or stays (up to the small change of the linearisation point), and the inputs' own SDs fall
// below their noise.
TEST(MapEstimator, UncertaintyShrinksAsMeasurementsAreAdded) {
  const auto model = female();
  Eigen::VectorXd truth = Eigen::VectorXd::Zero(model->shape_count());
  truth(0) = 0.5;
  truth(1) = 0.8;
  truth(4) = -0.6;
  const std::vector<std::vector<std::string>> sets = {
      {"stature", "weight"},
      {"stature", "weight", "span", "crotch_height"},
      kR6,
      {"stature", "weight", "span", "crotch_height", "hip_breadth", "arm_length", "chest_circumference",
       "waist_circumference", "buttock_circumference"}};
  const MapEstimator estimator(model);
  std::vector<MapEstimate> results;
  for (const auto& set : sets) results.push_back(estimator.estimate(measure_named(*model, truth, set)));
  for (size_t s = 1; s < results.size(); ++s) {
    const MapEstimate &fewer = results[s - 1], &more = results[s];
    int shrunk = 0;
    for (const auto& [name, sd] : more.measurement_sd) {
      const double before = fewer.measurement_sd.at(name);
      EXPECT_LE(sd, before * 1.02 + 1e-4) << name << " with " << sets[s].size() << " inputs";
      if (sd < before * 0.98) ++shrunk;
    }
    EXPECT_GT(shrunk, 0);
    EXPECT_LT(more.vertex_sd.mean(), fewer.vertex_sd.mean());
    for (Eigen::Index v = 0; v < more.vertex_sd.size(); ++v)
      ASSERT_LE(more.vertex_sd(v), fewer.vertex_sd(v) * 1.02 + 1e-4) << "vertex " << v;
    EXPECT_LT(more.covariance.trace(), fewer.covariance.trace());
  }
  // An input's posterior SD is below the noise it was weighed with (the gross-error stage may
  // only have widened that, never narrowed it).
  for (const auto& r : results)
    for (const auto& [name, fit] : r.inputs) {
      EXPECT_GE(fit.effective_sd, fit.noise_sd * (1 - 1e-12)) << name;
      EXPECT_LT(r.measurement_sd.at(name), fit.effective_sd) << name;
    }
  // With nothing known but the prior's mean, a measurement's SD is its population SD; two inputs
  // already cut stature's to below its noise SD.
  EXPECT_LT(results[0].measurement_sd.at("stature"), table2_sd(NoiseSetting::Self).at("stature"));
}

// Calibration: bodies drawn from the prior, measured, perturbed with noise of exactly the
// assumed SD. If the Laplace posterior is right, each true β_k lies within ±1 / ±2 predicted SD
// 68.3 % / 95.4 % of the time. 40 bodies × 10 values = 400 checks: the binomial SD of the shares
// is 1.1 % (2 SD) and 2.3 % (1 SD); the 10 values of one body are correlated through the shared
// noise, which can inflate that by up to √10 ≈ 3.2 in the worst case. The windows below are
// therefore ±5 % around 95.4 % and ±10 % around 68.3 %: wide enough for chance with this fixed seed,
// narrow enough to catch a covariance off by a factor 1.5 (its ±2 SD share would be ~82 %).
TEST(MapEstimator, PredictedSdIsCalibratedOnSyntheticBodies) {
  const auto model = female();
  const MapEstimator estimator(model);
  const std::vector<std::string> inputs = {"stature", "weight", "span", "crotch_height", "hip_breadth",
                                           "arm_length", "chest_circumference", "waist_circumference"};
  const std::vector<std::string> held_out = {"thigh_circumference", "biacromial_breadth", "waist_height"};
  MapOptions opt;
  opt.noise = NoiseSetting::Self;
  opt.vertex_uncertainty = false;
  opt.uncertainty_of = held_out;
  NormalGenerator rng(2024);
  const int bodies = 40;
  int within1 = 0, within2 = 0, checks = 0, m_within2 = 0, m_checks = 0;
  for (int b = 0; b < bodies; ++b) {
    Eigen::VectorXd truth(model->shape_count());
    for (auto& x : truth) x = rng.normal();
    auto all = inputs;
    all.insert(all.end(), held_out.begin(), held_out.end());
    const auto exact = measure_named(*model, truth, all);
    std::map<std::string, double> noisy;
    for (const auto& name : inputs) noisy[name] = exact.at(name) + rng.normal() * default_noise_sd(*model, name, opt.noise);
    const MapEstimate est = estimator.estimate(noisy, opt);
    for (Eigen::Index k = 0; k < truth.size(); ++k) {
      const double z = std::abs(est.beta(k) - truth(k)) / std::sqrt(est.covariance(k, k));
      within1 += z <= 1;
      within2 += z <= 2;
      ++checks;
    }
    const auto achieved = measure_named(*model, est.beta, held_out);
    for (const auto& name : held_out) {
      m_within2 += std::abs(achieved.at(name) - exact.at(name)) <= 2 * est.measurement_sd.at(name);
      ++m_checks;
    }
  }
  const double share1 = double(within1) / checks, share2 = double(within2) / checks;
  EXPECT_NEAR(share2, 0.954, 0.05) << "±2 SD share";
  EXPECT_NEAR(share1, 0.683, 0.10) << "±1 SD share";
  // Held-out measurements: 120 checks, also within ±2 predicted SD about 95 % of the time.
  EXPECT_NEAR(double(m_within2) / m_checks, 0.954, 0.08) << "held-out measurements within ±2 SD";
}

// Thread safety: one estimator, two threads, same answers as one thread.
TEST(MapEstimator, ConcurrentEstimatesAgree) {
  const auto model = female();
  const MapEstimator estimator(model);
  MapOptions opt;
  opt.measurement_uncertainty = false;
  opt.vertex_uncertainty = false;
  const auto a = measure_named(*model, Eigen::VectorXd::Constant(model->shape_count(), 0.3), kR6);
  const auto b = measure_named(*model, Eigen::VectorXd::Constant(model->shape_count(), -0.4), kR6);
  const Eigen::VectorXd ra = estimator.estimate(a, opt).beta, rb = estimator.estimate(b, opt).beta;
  Eigen::VectorXd ta, tb;
  std::thread t1([&] { ta = estimator.estimate(a, opt).beta; });
  std::thread t2([&] { tb = estimator.estimate(b, opt).beta; });
  t1.join();
  t2.join();
  EXPECT_EQ(ta, ra);
  EXPECT_EQ(tb, rb);
}

// The exact linearisation the estimator relies on: each measurement's vertex gradient, moved
// along a shape direction, must match a central finite difference of the measurement itself.
TEST(MeasurementGradient, MatchesFiniteDifferencesAlongShapeDirections) {
  const BodyModel& model = *female();
  NormalGenerator rng(7);
  Eigen::VectorXd beta(model.shape_count());
  for (Eigen::Index i = 0; i < beta.size(); ++i) beta(i) = 0.7 * rng.normal();
  const Vertices rest = model.rest_vertices(beta);
  const Eigen::MatrixXd& s = model.data().shape_directions;
  constexpr double kStep = 1e-4;
  for (const auto& def : model.data().measurements) {
    const MeasurementGradient g = measure_with_gradient(model, def, rest, model.faces());
    EXPECT_NEAR(g.value, measure(model, def, rest), 1e-12) << def.name;
    for (int j = 0; j < std::min(3, model.shape_count()); ++j) {
      double predicted = 0;
      for (const auto& term : g.terms) predicted += term.d.dot(s.col(j).segment<3>(3 * term.vertex));
      if (g.dense.size()) predicted += g.dense.dot(s.col(j));
      Vertices up = rest, down = rest;
      Eigen::Map<Eigen::VectorXd>(up.data(), up.size()) += kStep * s.col(j);
      Eigen::Map<Eigen::VectorXd>(down.data(), down.size()) -= kStep * s.col(j);
      const double numeric = (measure(model, def, up) - measure(model, def, down)) / (2 * kStep);
      // Hull corners and extreme points may switch within the step; 2 % or 0.5 mm per SD.
      EXPECT_NEAR(predicted, numeric, std::max(5e-4, 0.02 * std::abs(numeric))) << def.name << " along S_" << j;
    }
  }
}
