// The same person heavier or lighter at the same stature (avatar_weight_change.h), on the
// committed built-in body: stature and bone lengths stay, weight and girths follow the change,
// 0 % is the original, bad changes are refused naming the field.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "caliper/caliper.h"
#include "fixtures.h"

using namespace caliper;

namespace {

const AvatarBuilder& female_builder() {
  static const AvatarBuilder builder(std::make_shared<const BodyModel>(load_model("mannequin", Sex::Female)));
  return builder;
}

// A woman measured with the six Virtual Caliper inputs (cm, kg).
Avatar measured_woman() {
  AvatarRequest r;
  r.measurements = measurements_from_edge(
      {{"stature", 165}, {"weight", 62}, {"span", 166}, {"crotch_height", 77}, {"hip_breadth", 36}, {"arm_length", 55}});
  return female_builder().build(r);
}

double measured(const Avatar& a, const std::string& name) {
  return measure_some(female_builder().model(), {name}, a.rest_vertices).at(name);
}

}  // namespace

TEST(WeightChange, KeepsStatureAndLengthsWhileWeightAndGirthsGrow) {
  const Avatar original = measured_woman();
  const std::vector<double> pcts = {-30, -20, -10, 0, 10, 20, 30};
  const std::vector<Avatar> bodies = with_weight_changes(female_builder(), original, pcts);
  ASSERT_EQ(bodies.size(), pcts.size());
  const double stature = measured(original, "stature"), weight = measured(original, "weight");
  const double span = measured(original, "span"), crotch = measured(original, "crotch_height");
  double previous_weight = 0, previous_waist = 0;
  for (size_t i = 0; i < bodies.size(); ++i) {
    SCOPED_TRACE(pcts[i]);
    const Avatar& b = bodies[i];
    EXPECT_NEAR(measured(b, "stature"), stature, 0.003);  // 3 mm
    EXPECT_NEAR(measured(b, "span"), span, 0.01);
    EXPECT_NEAR(measured(b, "crotch_height"), crotch, 0.01);
    // The change asked for, within 3 % of the body's weight (the estimator's, not a scale).
    const double w = measured(b, "weight");
    EXPECT_NEAR(w, weight * (1 + pcts[i] / 100), 0.03 * weight);
    const double waist = measured(b, "waist_circumference");
    if (i > 0) {
      EXPECT_GT(w, previous_weight);
      EXPECT_GT(waist, previous_waist);
    }
    previous_weight = w;
    previous_waist = waist;
    EXPECT_EQ(b.rest_vertices.rows(), original.rest_vertices.rows());
    EXPECT_EQ(b.joints.rows(), original.joints.rows());
  }
}

TEST(WeightChange, ZeroIsTheOriginalAvatar) {
  const Avatar original = measured_woman();
  const Avatar same = with_weight_change(female_builder(), original, 0);
  EXPECT_EQ(same.beta, original.beta);
  EXPECT_EQ((same.rest_vertices - original.rest_vertices).cwiseAbs().maxCoeff(), 0.0);
  // A small change stays close to it: the bodies form a continuous series, no jump at 0.
  const Avatar near = with_weight_change(female_builder(), original, 1);
  EXPECT_LT((near.rest_vertices - original.rest_vertices).rowwise().norm().maxCoeff(), 0.01);
  EXPECT_GT((near.rest_vertices - original.rest_vertices).rowwise().norm().maxCoeff(), 0.0);
}

TEST(WeightChange, NotAScaledBody) {
  // A uniform scale giving +20 % weight would make her 6 % taller (1.2^(1/3)); the shoulders
  // between the acromions are bone and stay within a centimetre.
  const Avatar original = measured_woman();
  const Avatar heavier = with_weight_change(female_builder(), original, 20);
  EXPECT_NEAR(measured(heavier, "biacromial_breadth"), measured(original, "biacromial_breadth"), 0.01);
  EXPECT_GT(measured(heavier, "waist_circumference"), measured(original, "waist_circumference") + 0.03);
}

TEST(WeightChange, WorksWhenNoWeightWasGiven) {
  AvatarRequest r;
  r.measurements = measurements_from_edge({{"stature", 170}, {"span", 172}});
  const Avatar original = female_builder().build(r);
  const std::vector<Avatar> b = with_weight_changes(female_builder(), original, {-10, 10});
  EXPECT_LT(measured(b[0], "weight"), measured(original, "weight"));
  EXPECT_GT(measured(b[1], "weight"), measured(original, "weight"));
  EXPECT_NEAR(measured(b[1], "stature"), 1.70, 0.003);
}

TEST(WeightChange, RefusesBadChangesNamingTheFieldAndRange) {
  const Avatar original = measured_woman();
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}) {
    const Error e = test::catch_error([&] { with_weight_change(female_builder(), original, bad); });
    EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
    EXPECT_EQ(e.field(), "weight_change_pct");
    EXPECT_NE(std::string(e.what()).find("[-50, 100]"), std::string::npos) << e.what();
  }
  for (double bad : {-50.5, 100.1, -90.0, 1e9}) {
    const Error e = test::catch_error([&] { with_weight_changes(female_builder(), original, {10, bad}); });
    EXPECT_EQ(e.kind(), ErrorKind::OutOfRange);
    EXPECT_EQ(e.field(), "weight_change_pct");
    EXPECT_NE(std::string(e.what()).find("[-50, 100]"), std::string::npos) << e.what();
  }
  const Error e = test::catch_error([] { check_weight_change(120, "--weight-change"); });
  EXPECT_EQ(e.field(), "--weight-change");
  EXPECT_NO_THROW(check_weight_change(-50));
  EXPECT_NO_THROW(check_weight_change(100));
}

TEST(WeightChange, WhichMeasurementsFollowWeight) {
  for (const char* m : {"weight", "hip_breadth", "waist_breadth", "chest_depth", "waist_circumference", "calf_circumference"})
    EXPECT_TRUE(follows_body_weight(m)) << m;
  for (const char* m : {"stature", "span", "crotch_height", "arm_length", "biacromial_breadth", "head_breadth", "knee_height"})
    EXPECT_FALSE(follows_body_weight(m)) << m;
}

