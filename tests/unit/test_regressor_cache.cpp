// An AvatarBuilder keeps the paper's presets for good and at most kMaxCustomRegressors other
// input lists (least recently used dropped): a server asked for every subset of the catalogue
// keeps a bounded number of regressors, and a dropped one is retrained to the same body.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "caliper/caliper.h"

namespace caliper {
namespace {

TEST(RegressorCache, CustomRegressorsAreBoundedAndRetrainedAfterEviction) {
  auto model = std::make_shared<const BodyModel>(load_model("mannequin", Sex::Female));
  AvatarBuilder builder(model);
  const std::vector<std::string> names = preset_inputs("R6");  // six measurements: 63 subsets
  ASSERT_EQ(names.size(), 6u);
  AvatarRequest request;
  request.measurements = measurements_from_edge(
      {{"stature", 168}, {"weight", 62}, {"span", 170}, {"crotch_height", 78}, {"hip_breadth", 36}, {"arm_length", 57}});
  request.measure_avatar = false;
  auto regressor_for = [&](int mask) {
    std::string list;
    for (int i = 0; i < 6; ++i)
      if (mask & (1 << i)) list += (list.empty() ? "" : ",") + names[i];
    return list;
  };
  const int count = static_cast<int>(AvatarBuilder::kMaxCustomRegressors) + 12;
  ASSERT_LE(count, 63);
  Eigen::VectorXd first_beta;
  for (int mask = 1; mask <= count; ++mask) {
    request.regressor = regressor_for(mask);
    const Avatar a = builder.build(request);
    if (mask == 1) first_beta = a.beta;
    EXPECT_LE(builder.custom_regressor_count(), AvatarBuilder::kMaxCustomRegressors);
  }
  EXPECT_EQ(builder.custom_regressor_count(), AvatarBuilder::kMaxCustomRegressors);
  // Presets are not custom and never dropped.
  request.regressor = "R5";
  builder.build(request);
  EXPECT_EQ(builder.custom_regressor_count(), AvatarBuilder::kMaxCustomRegressors);
  // The first one was dropped long ago: retrained, the same body.
  request.regressor = regressor_for(1);
  const Avatar again = builder.build(request);
  ASSERT_EQ(again.beta.size(), first_beta.size());
  EXPECT_LT((again.beta - first_beta).norm(), 1e-9);
  EXPECT_EQ(builder.custom_regressor_count(), AvatarBuilder::kMaxCustomRegressors);
}

}  // namespace
}  // namespace caliper
