// Evaluation on real people: the JSON's shape, Table 1 behaviour (inputs reproduced, unused
// inputs not), noise, reproducibility. Needs the ANSUR II development data in ../shared.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "caliper/errors.h"
#include "caliper/evaluation/evaluate.h"
#include "caliper/io/model_files.h"

using namespace caliper;

namespace {

std::vector<AnsurSubject> first_subjects(int per_sex) {
  const std::string dir = std::string(CALIPER_SHARED_DIR) + "/data/ansur2";
  std::vector<AnsurSubject> out;
  for (const char* f : {"/ANSUR_II_FEMALE_dev.csv", "/ANSUR_II_MALE_dev.csv"}) {
    auto all = read_ansur_csv(dir + f);
    out.insert(out.end(), all.begin(), all.begin() + std::min<size_t>(all.size(), static_cast<size_t>(per_sex)));
  }
  return out;
}

std::function<std::shared_ptr<const AvatarBuilder>(Sex)> builders() {
  auto cache = std::make_shared<std::map<Sex, std::shared_ptr<const AvatarBuilder>>>();
  return [cache](Sex sex) {
    auto& b = (*cache)[sex];
    if (!b) b = std::make_shared<const AvatarBuilder>(std::make_shared<const BodyModel>(load_model("mannequin", sex)));
    return b;
  };
}

bool have_data() {
  return std::filesystem::exists(std::string(CALIPER_SHARED_DIR) + "/data/ansur2/ANSUR_II_FEMALE_dev.csv");
}

}  // namespace

TEST(Evaluation, Table2NoiseAndNames) {
  EXPECT_TRUE(table2_mae(MeasurementNoise::None).empty());
  EXPECT_DOUBLE_EQ(table2_mae(MeasurementNoise::Self).at("stature"), 0.0153);
  EXPECT_DOUBLE_EQ(table2_mae(MeasurementNoise::Other).at("crotch_height"), 0.0246);
  EXPECT_THROW(parse_noise("loud"), Error);
  EXPECT_EQ(held_out_columns().size(), 12u);
}

TEST(Evaluation, InputsReproducedAndJsonShape) {
  if (!have_data()) GTEST_SKIP() << "ANSUR II development data not found in " << CALIPER_SHARED_DIR;
  const auto subjects = first_subjects(40);
  EvaluationOptions opt;
  opt.regressors = {"R2", "R5"};
  const Evaluation ev = evaluate_subjects(subjects, builders(), opt);
  EXPECT_EQ(ev.subjects, 80);
  const auto& r5 = ev.regressors.at("R5");
  for (const char* in : {"stature", "span", "crotchheight", "hipbreadth"}) {
    EXPECT_EQ(r5.inputs.at(in).count, 80) << in;
    EXPECT_LT(r5.inputs.at(in).max, 0.002) << in;  // metres: reproduced (paper Table 1)
  }
  EXPECT_LT(r5.inputs.at("weight").mae, 1.0);  // kg
  // R2 does not use span: it is held out for R2, with errors of centimetres, not zero.
  EXPECT_FALSE(ev.regressors.at("R2").inputs.count("span"));
  EXPECT_GT(ev.regressors.at("R2").held_out.at("span").mae, 0.005);
  EXPECT_TRUE(ev.baselines.count("uniform_scale"));
  EXPECT_TRUE(ev.baselines.count("R2"));
  const auto j = nlohmann::json::parse(evaluation_json(ev));
  EXPECT_EQ(j["subjects"], 80);
  EXPECT_TRUE(j["regressors"]["R5"]["inputs"]["stature"].contains("mae_cm"));
  EXPECT_TRUE(j["regressors"]["R5"]["inputs"]["weight"].contains("max_kg"));
  EXPECT_TRUE(j["regressors"]["R5"]["held_out"]["chestcircumference"].contains("bias_cm"));
  EXPECT_TRUE(j["baselines"]["uniform_scale"]["held_out"].contains("waistcircumference"));
  // Held-out circumferences are predicted, not reproduced: errors of the order of ANSUR's own
  // linear-regression baseline (3-4 cm for waist), far from both zero and absurd.
  const double waist = r5.held_out.at("waistcircumference").mae;
  EXPECT_GT(waist, 0.01);
  EXPECT_LT(waist, 0.10);
}

TEST(Evaluation, NoiseIsSeededAndMatters) {
  if (!have_data()) GTEST_SKIP() << "ANSUR II development data not found in " << CALIPER_SHARED_DIR;
  const auto subjects = first_subjects(25);
  EvaluationOptions opt;
  opt.regressors = {"R4"};
  opt.baselines = false;
  opt.noise = MeasurementNoise::Self;
  opt.seed = 5;
  const Evaluation a = evaluate_subjects(subjects, builders(), opt);
  opt.threads = 1;  // same numbers whatever the threading
  const Evaluation b = evaluate_subjects(subjects, builders(), opt);
  EXPECT_EQ(evaluation_json(a), evaluation_json(b));
  opt.noise = MeasurementNoise::None;
  const Evaluation clean = evaluate_subjects(subjects, builders(), opt);
  // With noisy inputs the avatars miss the true held-out stature-driven heights by more.
  EXPECT_GT(a.regressors.at("R4").held_out.at("acromialheight").mae,
            clean.regressors.at("R4").held_out.at("acromialheight").mae);
}
