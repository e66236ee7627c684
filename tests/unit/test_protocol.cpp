// ISAK rule and real → virtual maps (paper §3.1, §3.3).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "caliper/caliper.h"

using namespace caliper;

TEST(Isak, TwoCloseValuesGiveTheirMean) {
  const IsakResult r = isak_combine({100.0, 101.0});
  EXPECT_EQ(r.rule, IsakRule::MeanOfTwo);
  EXPECT_DOUBLE_EQ(*r.value, 100.5);
}

TEST(Isak, ExactlyOnePointFivePercentNeedsAThird) {
  // 1.5 % of the mean apart is not "less than 1.5 %".
  const IsakResult r = isak_combine({99.25, 100.75});
  EXPECT_NEAR(r.relative_difference, 0.015, 1e-12);
  EXPECT_EQ(r.rule, IsakRule::NeedThird);
  EXPECT_FALSE(r.value.has_value());
}

TEST(Isak, FarApartUsesMedianOfThree) {
  const IsakResult r = isak_combine({100.0, 110.0, 103.0});
  EXPECT_EQ(r.rule, IsakRule::MedianOfThree);
  EXPECT_DOUBLE_EQ(*r.value, 103.0);
}

TEST(Isak, ThirdIgnoredWhenFirstTwoAgree) {
  const IsakResult r = isak_combine({100.0, 100.2, 150.0});
  EXPECT_EQ(r.rule, IsakRule::MeanOfTwo);
  EXPECT_DOUBLE_EQ(*r.value, 100.1);
}

TEST(Isak, BadInput) {
  EXPECT_THROW(isak_combine({100.0}), Error);
  EXPECT_THROW(isak_combine({100.0, 1, 2, 3}), Error);
  EXPECT_THROW(isak_combine({100.0, std::nan("")}), Error);
  EXPECT_THROW(isak_combine({-1.0, 100.0}), Error);
}

TEST(RealToVirtual, IdentityByDefault) {
  RealToVirtual m;
  std::map<std::string, double> v = {{"hip_breadth", 0.35}};
  m.apply(v);
  EXPECT_DOUBLE_EQ(v["hip_breadth"], 0.35);
}

TEST(RealToVirtual, FitRecoversAKnownLine) {
  const auto dir = std::filesystem::temp_directory_path() / "caliper_map_test";
  std::filesystem::create_directories(dir);
  const auto csv = (dir / "pairs.csv").string();
  {
    std::ofstream f(csv);
    f << "measurement,real_cm,virtual_cm\r\n";
    for (double real : {30.0, 33.0, 35.0, 38.0, 41.0}) f << "hip_width," << real << "," << 0.9 * real + 2.0 << "\r\n";
  }
  const RealToVirtual m = RealToVirtual::fit_csv(csv);
  const LinearMap& hip = m.map("hip_breadth");  // alias resolved to the canonical name
  EXPECT_NEAR(hip.slope, 0.9, 1e-12);
  EXPECT_NEAR(hip.offset, 0.02, 1e-12);
  EXPECT_EQ(hip.pairs, 5);
  // Save → load round trip.
  const auto json = (dir / "map.json").string();
  m.save(json);
  const RealToVirtual back = RealToVirtual::load(json);
  EXPECT_NEAR(back.map("hip_breadth").slope, 0.9, 1e-12);
  EXPECT_NEAR(back.map("hip_breadth").apply(0.35), 0.9 * 0.35 + 0.02, 1e-12);
  std::filesystem::remove_all(dir);
}

// Audit (docs/reliability.md): a wrong type ("pairs": "20") escaped from_json as nlohmann's
// type_error, which the CLI reports as an internal error, and "pairs": 1e300 was cast to int
// (undefined behaviour). Each is now Error(Format) naming the field and, for integers, the range.
TEST(RealToVirtual, MalformedFieldsAreFormatErrorsNamingTheField) {
  const auto error_of = [](const std::string& text) {
    try {
      RealToVirtual::from_json(text);
    } catch (const Error& e) {
      return std::make_pair(e.kind(), std::string(e.field()) + " | " + e.what());
    } catch (const std::exception& e) {
      return std::make_pair(ErrorKind::Unsupported, std::string("not a caliper::Error: ") + e.what());
    }
    return std::make_pair(ErrorKind::Unsupported, std::string("no error"));
  };
  const auto map_with = [](const std::string& entry) {
    return R"({"format": "caliper-real-to-virtual", "maps": {"hip_breadth": )" + entry + "}}";
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {map_with(R"({"slope": 0.9, "pairs": "20"})"), "maps.hip_breadth.pairs"},
      {map_with(R"({"slope": 0.9, "pairs": 1e300})"), "maps.hip_breadth.pairs"},
      {map_with(R"({"slope": 0.9, "pairs": -3})"), "maps.hip_breadth.pairs"},
      {map_with(R"({"slope": 0.9, "pairs": 2.5})"), "maps.hip_breadth.pairs"},
      {map_with(R"({"slope": 0.9, "pairs": 18446744073709551615})"), "maps.hip_breadth.pairs"},
      {map_with(R"({"slope": 0.9, "rmse_cm": "0.4"})"), "maps.hip_breadth.rmse_cm"},
      {map_with(R"({"slope": 0.9, "offset_cm": [1]})"), "maps.hip_breadth.offset_cm"},
      {map_with(R"({"offset_cm": 1.2})"), "maps.hip_breadth.slope"},
      {map_with("3"), "maps.hip_breadth"},
      {R"({"format": 5, "maps": {}})", "format"},
      {R"({"format": "caliper-real-to-virtual"})", "maps"},
      {R"({"format": "caliper-real-to-virtual", "maps": [1]})", "maps"},
  };
  for (const auto& [text, field] : cases) {
    const auto [kind, what] = error_of(text);
    EXPECT_EQ(kind, ErrorKind::Format) << text << " -> " << what;
    EXPECT_EQ(what.substr(0, what.find(" | ")), field) << text << " -> " << what;
  }
  EXPECT_NE(error_of(map_with(R"({"slope": 0.9, "pairs": 1e300})")).second.find("[0, 2147483647]"), std::string::npos);
  const RealToVirtual ok = RealToVirtual::from_json(map_with(R"({"slope": 0.9, "pairs": 20.0, "rmse_cm": null})"));
  EXPECT_EQ(ok.map("hip_breadth").pairs, 20);
}

TEST(RealToVirtual, BadFiles) {
  EXPECT_THROW(RealToVirtual::from_json("{not json"), Error);
  EXPECT_THROW(RealToVirtual::from_json(R"({"format":"other","maps":{}})"), Error);
  EXPECT_THROW(RealToVirtual::from_json(R"({"format":"caliper-real-to-virtual","maps":{"hip_breadth":{"slope":"x"}}})"), Error);
  EXPECT_THROW(RealToVirtual::from_json(R"({"format":"caliper-real-to-virtual","maps":{"hip_breadth":{"slope":-1}}})"), Error);
  EXPECT_THROW(RealToVirtual::from_json(R"({"format":"caliper-real-to-virtual","maps":{"nose":{"slope":1}}})"), Error);
  EXPECT_THROW(RealToVirtual::load("/nonexistent/map.json"), Error);
}
