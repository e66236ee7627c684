// Held-out validation of the number of shape directions on a small subset of the
// ANSUR II development data: the curve has the properties the method guarantees (nested PCA:
// variance kept rises and reconstruction error falls with K; every subject judged once), and
// bad options are refused naming the field.
#include <gtest/gtest.h>

#include <filesystem>

#include "caliper/errors.h"
#include "caliper/evaluation/evaluate.h"
#include "caliper/evaluation/shape_count.h"

using namespace caliper;

namespace {

const std::string kFemale = std::string(CALIPER_SHARED_DIR) + "/data/ansur2/ANSUR_II_FEMALE_dev.csv";

}  // namespace

TEST(ShapeCount, CurveOnASmallSubset) {
  if (!std::filesystem::exists(kFemale)) GTEST_SKIP() << "ANSUR II development data not found in " << CALIPER_SHARED_DIR;
  std::vector<AnsurSubject> subjects = read_ansur_csv(kFemale);
  subjects.resize(40);
  ShapeCountOptions options;
  options.counts = {2, 6, 12};
  options.folds = 2;
  int calls = 0;
  options.progress = [&](const std::string&, int, int) { ++calls; };
  const std::vector<ShapeCountPoint> curve = validate_shape_counts(subjects, Sex::Female, options);
  ASSERT_EQ(curve.size(), 3u);
  EXPECT_GT(calls, 0);
  for (size_t i = 0; i < curve.size(); ++i) {
    EXPECT_EQ(curve[i].k, options.counts[i]);
    EXPECT_EQ(curve[i].failures, 0);
    EXPECT_GT(curve[i].explained, 0.5);
    EXPECT_LE(curve[i].explained, 1.0);
    // Every held-out column of the evaluation is predicted, with a sane error (cm, not metres).
    EXPECT_EQ(curve[i].held_out_mae.size(), held_out_columns().size());
    EXPECT_GT(curve[i].mean_held_out_mae_cm, 0.1);
    EXPECT_LT(curve[i].mean_held_out_mae_cm, 20.0);
    if (i == 0) continue;
    EXPECT_GT(curve[i].explained, curve[i - 1].explained);
    EXPECT_LT(curve[i].reconstruction_mm, curve[i - 1].reconstruction_mm);
  }
}

TEST(ShapeCount, RefusesBadOptions) {
  ShapeCountOptions options;
  options.counts = {0};
  try {
    validate_shape_counts({}, Sex::Female, options);
    FAIL() << "K = 0 accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "counts");
  }
  options.counts = {5};
  options.folds = 1;
  EXPECT_THROW(validate_shape_counts({}, Sex::Female, options), Error);
  options.counts = {};
  options.folds = 2;
  EXPECT_THROW(validate_shape_counts({}, Sex::Female, options), Error);
}
