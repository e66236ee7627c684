// The linear limit of `caliper eval` on a synthetic population with a known answer:
// columns that are exact linear functions of the inputs are recovered, noise added to a column
// shows up as its MAE, and every method is compared with the limit from its own inputs.
#include <gtest/gtest.h>

#include <cmath>

#include "caliper/errors.h"
#include "caliper/evaluation/evaluate.h"
#include "caliper/evaluation/linear_limit.h"
#include "caliper/random.h"

using namespace caliper;

namespace {

// n people whose inputs vary independently; chest circumference = 0.2 + 0.3·stature + 0.004·weight
// exactly, waist circumference the same plus Gaussian noise of SD `noise` (metres).
std::vector<AnsurSubject> synthetic_people(int n, double noise, std::uint64_t seed) {
  NormalGenerator rng(seed);
  std::vector<AnsurSubject> out;
  for (int i = 0; i < n; ++i) {
    AnsurSubject s;
    s.id = std::to_string(i);
    s.sex = Sex::Female;
    auto& v = s.values;
    v["stature"] = 1.65 + 0.07 * rng.normal();
    v["weightkg"] = 65 + 10 * rng.normal();
    v["span"] = 1.67 + 0.08 * rng.normal();
    v["crotchheight"] = 0.78 + 0.04 * rng.normal();
    v["hipbreadth"] = 0.35 + 0.02 * rng.normal();
    v["acromionradialelength"] = 0.31 + 0.015 * rng.normal();
    v["radialestylionlength"] = 0.24 + 0.012 * rng.normal();
    v["chestcircumference"] = 0.2 + 0.3 * v["stature"] + 0.004 * v["weightkg"];
    v["waistcircumference"] = v["chestcircumference"] + noise * rng.normal();
    out.push_back(s);
  }
  return out;
}

std::vector<const AnsurSubject*> pointers(const std::vector<AnsurSubject>& people) {
  std::vector<const AnsurSubject*> out;
  for (const auto& s : people) out.push_back(&s);
  return out;
}

}  // namespace

TEST(LinearLimit, RecoversAnExactLinearColumn) {
  const auto people = synthetic_people(200, 0.0, 3);
  const LinearLimit limit(pointers(people), {"stature", "weight"}, {"chestcircumference"});
  const Eigen::VectorXd& b = limit.coefficients("chestcircumference");
  EXPECT_NEAR(b(0), 0.2, 1e-9);
  EXPECT_NEAR(b(1), 0.3, 1e-9);
  EXPECT_NEAR(b(2), 0.004, 1e-11);
  EXPECT_NEAR(limit.predict("chestcircumference", {{"stature", 1.8}, {"weight", 80.0}, {"span", 2.0}}),
              0.2 + 0.3 * 1.8 + 0.004 * 80, 1e-9);
}

TEST(LinearLimit, NoiseInTheColumnIsWhatRemains) {
  // Fitted on one population and tested on another: the MAE left is the noise's, SD·√(2/π).
  const double sd = 0.02;
  const auto training = synthetic_people(2000, sd, 5), tested = synthetic_people(2000, sd, 6);
  const LinearLimit limit(pointers(training), {"stature", "weight", "span"}, {"waistcircumference"});
  double mae = 0;
  for (const auto& s : tested)
    mae += std::abs(limit.predict("waistcircumference", virtual_caliper_inputs(s)) - s.values.at("waistcircumference"));
  mae /= static_cast<double>(tested.size());
  EXPECT_NEAR(mae, sd * std::sqrt(2 / M_PI), 0.06 * sd * std::sqrt(2 / M_PI));
}

TEST(LinearLimit, RefusesWhatItCannotFit) {
  const auto people = synthetic_people(5, 0.0, 7);
  EXPECT_THROW(LinearLimit(pointers(people), {"chest_circumference"}, {"waistcircumference"}), Error);
  EXPECT_THROW(LinearLimit(pointers(people), {"stature", "weight", "span", "crotch_height", "hip_breadth"},
                           {"waistcircumference"}),
               Error);  // 5 people for 6 coefficients
  const LinearLimit limit(pointers(people), {"stature"}, {"chestcircumference"});
  EXPECT_THROW(limit.predict("waistcircumference", {{"stature", 1.7}}), Error);
  EXPECT_THROW(limit.predict("chestcircumference", {{"weight", 70.0}}), Error);
}

// Each method is compared with the limit from its own inputs: R2's uses stature and weight,
// auto's all six, the uniformly scaled mean body's stature alone.
TEST(LinearLimit, MethodsUseTheirOwnInputs) {
  EXPECT_EQ(method_inputs("R2"), (std::vector<std::string>{"stature", "weight"}));
  EXPECT_EQ(method_inputs("baseline:R2"), (std::vector<std::string>{"stature", "weight"}));
  EXPECT_EQ(method_inputs("R5").size(), 5u);
  EXPECT_EQ(method_inputs("auto").size(), 6u);
  EXPECT_EQ(method_inputs("map"), method_inputs("auto"));
  EXPECT_EQ(method_inputs("baseline:uniform_scale"), (std::vector<std::string>{"stature"}));
  EXPECT_THROW(method_inputs("R7"), Error);
}
