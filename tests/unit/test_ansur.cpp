// ANSUR II CSV reading: the public format's quirks, and the real development files when present.
#include <gtest/gtest.h>

#include <filesystem>

#include "caliper/io/ansur.h"
#include "caliper/errors.h"

using namespace caliper;

TEST(Ansur, ParsesCaseInsensitiveHeaderCrlfAndNoFinalNewline) {
  const std::string text =
      "SubjectId,stature,weightkg,span,crotchheight,hipbreadth,acromionradialelength,radialestylionlength,Gender,Ethnicity\r\n"
      "1,1650,600,1700,780,350,310,240,Female,\r\n"
      "2,1800,855,1850,850,345,335,268,Male,M\xe9tis";
  const auto s = parse_ansur_csv(text, "test.csv");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].sex, Sex::Female);
  EXPECT_EQ(s[1].id, "2");
  EXPECT_DOUBLE_EQ(s[0].values.at("stature"), 1.65);
  EXPECT_DOUBLE_EQ(s[0].values.at("weightkg"), 60.0);  // tenths of kg
  const auto in = virtual_caliper_inputs(s[1]);
  EXPECT_NEAR(in.at("arm_length"), 0.603, 1e-12);
}

TEST(Ansur, ErrorsNameLineAndColumn) {
  try {
    parse_ansur_csv("stature,Gender\n1650,Female\nabc,Male\n", "x.csv");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("x.csv:3"), std::string::npos);
    EXPECT_EQ(e.field(), "stature");
  }
  EXPECT_THROW(parse_ansur_csv("stature,Gender\n1650\n", "x.csv"), Error);
  EXPECT_THROW(parse_ansur_csv("height,Gender\n1650,Female\n", "x.csv"), Error);
  EXPECT_THROW(read_ansur_csv("/nonexistent.csv"), Error);
}

// A row in centimetres (165 instead of 1650 mm) would make a 16.5 cm avatar: refused, naming the
// file, line, column and the accepted range. Columns a file lacks are not required.
TEST(Ansur, InputsOutsideTheAcceptedRangeAreRefused) {
  try {
    parse_ansur_csv("stature,weightkg,Gender\n1650,600,Female\n165,600,Female\n", "cm.csv");
    FAIL() << "a stature of 16.5 cm was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::OutOfRange);
    EXPECT_EQ(e.field(), "stature");
    const std::string m = e.what();
    EXPECT_NE(m.find("cm.csv:3"), std::string::npos) << m;
    EXPECT_NE(m.find("[50, 250] cm"), std::string::npos) << m;
  }
  EXPECT_THROW(parse_ansur_csv("stature,weightkg,Gender\n1650,6000,Female\n", "kg.csv"), Error);  // 600 kg
  EXPECT_THROW(parse_ansur_csv("stature,acromionradialelength,radialestylionlength,Gender\n1650,31,24,Male\n", "a.csv"),
               Error);  // arm length 5.5 cm
  EXPECT_EQ(parse_ansur_csv("stature,Gender\n1650,Female\n", "ok.csv").size(), 1u);
}

TEST(Ansur, DevelopmentFilesWhenPresent) {
  const std::string dir = std::string(CALIPER_SHARED_DIR) + "/data/ansur2";
  if (!std::filesystem::exists(dir + "/ANSUR_II_FEMALE_dev.csv"))
    GTEST_SKIP() << "ANSUR II development data not found at " << dir << " (it lives in ../shared beside the project)";
  const auto women = read_ansur_csv(dir + "/ANSUR_II_FEMALE_dev.csv");
  const auto men = read_ansur_csv(dir + "/ANSUR_II_MALE_dev.csv");
  EXPECT_EQ(women.size(), 1490u);  // the README's row counts
  EXPECT_EQ(men.size(), 3062u);
  double mean = 0;
  for (const auto& s : men) mean += s.values.at("stature") / men.size();
  EXPECT_NEAR(mean, 1.756, 0.01);  // README: 175.6 cm over the full file
}
