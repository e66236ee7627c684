// Typing mistakes in measurements: each pattern is caught with what was meant, and
// no real person of the ANSUR II development data is flagged.
#include <gtest/gtest.h>

#include <filesystem>

#include "caliper/io/ansur.h"
#include "caliper/measure/input_check.h"

using namespace caliper;

namespace {
const SuspectValue* find(const std::vector<SuspectValue>& all, const std::string& field) {
  for (const auto& s : all)
    if (s.field == field) return &s;
  return nullptr;
}
}  // namespace

TEST(InputCheck, HeightAndWeightSwapped) {
  const auto s = suspect_input_mistakes({{"stature", 60}, {"weight", 165}});
  ASSERT_EQ(s.size(), 2u);
  EXPECT_DOUBLE_EQ(find(s, "stature")->suggested, 165);
  EXPECT_DOUBLE_EQ(find(s, "weight")->suggested, 60);
  EXPECT_NE(describe_suspects(s).find("swapped"), std::string::npos);
  EXPECT_NE(describe_suspects(s).find("--force"), std::string::npos);
}

TEST(InputCheck, HeightInOtherUnits) {
  EXPECT_NEAR(find(suspect_input_mistakes({{"stature", 1.72}, {"weight", 70}}), "stature")->suggested, 172, 1e-9);
  EXPECT_NEAR(find(suspect_input_mistakes({{"stature", 1720}, {"weight", 70}}), "stature")->suggested, 172, 1e-9);
  const auto inches = suspect_input_mistakes({{"stature", 68}, {"weight", 70}});
  ASSERT_EQ(inches.size(), 1u);
  EXPECT_NEAR(inches[0].suggested, 68 * 2.54, 1e-9);
  EXPECT_NE(inches[0].reason.find("inches"), std::string::npos);
}

TEST(InputCheck, WeightInPounds) {
  const auto s = suspect_input_mistakes({{"stature", 165}, {"weight", 165}});
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].field, "weight");
  EXPECT_NEAR(s[0].suggested, 165 * 0.45359237, 1e-9);
  // A heavy person is not taken for pounds: BMI 47.8.
  EXPECT_TRUE(suspect_input_mistakes({{"stature", 165}, {"weight", 130}}).empty());
}

TEST(InputCheck, LengthsInOtherUnits) {
  const auto s = suspect_input_mistakes({{"stature", 165}, {"weight", 60}, {"span", 66}, {"hip_breadth", 360}, {"crotch_height", 0.78}});
  ASSERT_EQ(s.size(), 3u);
  EXPECT_NEAR(find(s, "span")->suggested, 66 * 2.54, 1e-9);
  EXPECT_NEAR(find(s, "hip_breadth")->suggested, 36, 1e-9);
  EXPECT_NEAR(find(s, "crotch_height")->suggested, 78, 1e-9);
  const auto fixed = apply_suggestions({{"stature", 165}, {"weight", 60}, {"span", 66}}, s);
  EXPECT_NEAR(fixed.at("span"), 167.64, 1e-9);
  EXPECT_TRUE(suspect_input_mistakes(fixed).empty() || !find(suspect_input_mistakes(fixed), "span"));
}

TEST(InputCheck, OrdinaryAndIncompleteValuesPass) {
  EXPECT_TRUE(suspect_input_mistakes({{"stature", 165}, {"weight", 60}, {"span", 167}, {"crotch_height", 78}}).empty());
  EXPECT_TRUE(suspect_input_mistakes({{"weight", 60}}).empty());
  EXPECT_TRUE(suspect_input_mistakes({}).empty());
  EXPECT_TRUE(suspect_input_mistakes({{"stature", 300}, {"weight", 60}}).empty());  // out of range: the range check says so
}

// No real person is doubted: every development subject's six inputs, as they would be typed.
TEST(InputCheck, NoAnsurSubjectIsFlagged) {
  const std::string dir = std::string(CALIPER_SHARED_DIR) + "/data/ansur2/";
  if (!std::filesystem::exists(dir + "ANSUR_II_FEMALE_dev.csv")) GTEST_SKIP() << "ANSUR II data not found in " << dir;
  int people = 0;
  for (const char* file : {"ANSUR_II_FEMALE_dev.csv", "ANSUR_II_MALE_dev.csv"})
    for (const auto& s : read_ansur_csv(dir + file)) {
      std::map<std::string, double> typed;
      for (const auto& [name, si] : virtual_caliper_inputs(s)) typed[name] = name == "weight" ? si : si * 100;
      const auto suspects = suspect_input_mistakes(typed);
      EXPECT_TRUE(suspects.empty()) << s.id << ": " << suspects.front().reason;
      ++people;
    }
  EXPECT_GT(people, 4000);
}
