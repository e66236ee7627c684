// The CSV readers as spreadsheets write them (capture/measurement_set.h, src/csv_table.h): the
// separator, quotes and decimal commas; the long, wide and ANSUR II layouts; bad rows skipped
// with line, field and range.
#include <gtest/gtest.h>

#include "caliper/capture/measurement_set.h"
#include "caliper/errors.h"
#include "csv_table.h"

namespace caliper {
namespace {

TEST(CsvTable, DetectsTheSeparatorAndReadsQuotedCells) {
  const auto semi = detail::split_csv("a;b;c\n1,5;\"x;y\";\n", "t");
  EXPECT_EQ(semi.separator, ';');
  ASSERT_EQ(semi.lines.size(), 2u);
  EXPECT_EQ(semi.lines[1].cells, (std::vector<std::string>{"1,5", "x;y", ""}));
  const auto comma = detail::split_csv("\xEF\xBB\xBF# a comment\r\n\r\nname, value \r\n\"say \"\"hi\"\"\",\"1,5\"", "t");
  EXPECT_EQ(comma.separator, ',');
  ASSERT_EQ(comma.lines.size(), 2u);
  EXPECT_EQ(comma.lines[0].number, 3);
  EXPECT_EQ(comma.lines[0].cells, (std::vector<std::string>{"name", "value"}));
  EXPECT_EQ(comma.lines[1].cells, (std::vector<std::string>{"say \"hi\"", "1,5"}));
  EXPECT_EQ(detail::split_csv("a\tb\n", "t").separator, '\t');
  try {
    detail::split_csv("a,b\n\"open,1\n", "file.csv");
    FAIL() << "an open quote was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("file.csv, line 2"), std::string::npos) << e.what();
  }
}

TEST(CsvTable, ReadsDecimalPointsAndCommasOnly) {
  EXPECT_EQ(detail::parse_decimal("165.5"), 165.5);
  EXPECT_EQ(detail::parse_decimal(" 165,5 "), 165.5);
  EXPECT_EQ(detail::parse_decimal("-2"), -2.0);
  for (const char* bad : {"", "165cm", "1,655.0", "1.655,0", "1,6,5", "abc", "165 5"})
    EXPECT_FALSE(detail::parse_decimal(bad).has_value()) << bad;
}

TEST(MeasurementSetCsv, ReadsTheLongLayoutWithSemicolonsAndQuotedCommas) {
  for (const char* text : {"measurement;value;unit\nsex;male;\nstature;180,5;cm\nweight;82;kg\n",
                           "measurement,value,unit\nsex,male,\nstature,\"180,5\",cm\nweight,82,kg\n",
                           "stature\t1805\tmm\nweight\t82\n"}) {
    const MeasurementSetFile set = parse_measurement_set(text);
    EXPECT_DOUBLE_EQ(set.edge.at("stature"), 180.5) << text;
    EXPECT_DOUBLE_EQ(set.edge.at("weight"), 82.0) << text;
  }
  // Four cells: a decimal comma that splits the row; the message says how to write it.
  try {
    parse_measurement_set("stature,180,5,cm\n");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Format);
    EXPECT_NE(std::string(e.what()).find("must be quoted"), std::string::npos) << e.what();
  }
}

TEST(MeasurementSetCsv, ReadsOnePersonInTheWideLayout) {
  const MeasurementSetFile set =
      parse_measurement_set("Participant;Sex;Height (cm);weight_kg;arm span;Inseam;hip-width;measured_by\n"
                            "P01;female;165,5;62;167;76;36;self\n");
  EXPECT_EQ(set.sex, Sex::Female);
  EXPECT_EQ(set.measured_by, "self");
  EXPECT_DOUBLE_EQ(set.edge.at("stature"), 165.5);
  EXPECT_DOUBLE_EQ(set.edge.at("weight"), 62.0);
  EXPECT_DOUBLE_EQ(set.edge.at("span"), 167.0);
  EXPECT_DOUBLE_EQ(set.edge.at("crotch_height"), 76.0);
  EXPECT_DOUBLE_EQ(set.edge.at("hip_breadth"), 36.0);
  // A unit in the header converts: 1.655 m and 136.7 lb.
  const MeasurementSetFile metric = parse_measurement_set("height_m,weight (lb)\n1.655,136.7\n");
  EXPECT_NEAR(metric.edge.at("stature"), 165.5, 1e-9);
  EXPECT_NEAR(metric.edge.at("weight"), 136.7 * 0.45359237, 1e-9);
  EXPECT_THROW(parse_measurement_set("id,height,weight\nA,165,60\nB,170,65\n"), Error);  // two people
  EXPECT_THROW(parse_measurement_set("id,height,weight\nA,1650,60\n"), Error);            // out of range
}

TEST(MeasurementTable, SkipsBadRowsNamingLineFieldAndRange) {
  const MeasurementTable t = parse_measurement_table(
      "id,sex,height,weight\n"
      "A,female,165,60\n"
      "B,female,165,600\n"       // weight out of range
      "C,female,abc,60\n"        // not a number
      "A,male,180,80\n"          // id repeated
      "D,male,,\n"               // nothing measured
      "E,male,180,80,9\n"        // one cell too many
      "F,male,\"180,5\",80\n");
  EXPECT_EQ(t.layout, "wide");
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0].participant, "A");
  EXPECT_EQ(t.rows[0].line, 2);
  EXPECT_EQ(t.rows[1].participant, "F");
  EXPECT_DOUBLE_EQ(t.rows[1].set.edge.at("stature"), 180.5);
  ASSERT_EQ(t.skipped.size(), 5u);
  EXPECT_EQ(t.skipped[0].line, 3);
  EXPECT_EQ(t.skipped[0].field, "weight");
  EXPECT_NE(t.skipped[0].reason.find("[10, 300] kg"), std::string::npos) << t.skipped[0].reason;
  EXPECT_EQ(t.skipped[1].line, 4);
  EXPECT_EQ(t.skipped[1].field, "stature");
  EXPECT_EQ(t.skipped[2].line, 5);
  EXPECT_NE(t.skipped[2].reason.find("already on line 2"), std::string::npos) << t.skipped[2].reason;
  EXPECT_EQ(t.skipped[3].line, 6);
  EXPECT_EQ(t.skipped[4].line, 7);
}

TEST(MeasurementTable, ReadsTheAnsurLayoutInMillimetres) {
  const MeasurementTable t = parse_measurement_table(
      "SubjectId,Gender,stature,weightkg,span,crotchheight,hipbreadth,acromionradialelength,radialestylionlength\n"
      "ex-1,Female,1642,645,1668,781,356,312,243\n"
      "ex-2,Male,1781,8420,1822,851,345,336,268\n");  // 842 kg: skipped
  EXPECT_EQ(t.layout, "ansur");
  ASSERT_EQ(t.rows.size(), 1u);
  EXPECT_EQ(t.rows[0].participant, "ex-1");
  EXPECT_EQ(t.rows[0].set.sex, Sex::Female);
  EXPECT_NEAR(t.rows[0].set.edge.at("stature"), 164.2, 1e-9);
  EXPECT_NEAR(t.rows[0].set.edge.at("weight"), 64.5, 1e-9);
  EXPECT_NEAR(t.rows[0].set.edge.at("arm_length"), 55.5, 1e-9);  // 312 + 243 mm
  ASSERT_EQ(t.skipped.size(), 1u);
  EXPECT_EQ(t.skipped[0].line, 3);
  EXPECT_NE(t.skipped[0].reason.find("tenths of a kilogram"), std::string::npos) << t.skipped[0].reason;
}

TEST(MeasurementTable, RefusesAFileThatIsNoTableNamingTheColumn) {
  try {
    parse_measurement_table("id,height,chest circ\nA,165,90\n");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Format);
    EXPECT_EQ(e.field(), "chest circ");
  }
  EXPECT_THROW(parse_measurement_table("id,height,Height (cm)\nA,165,165\n"), Error);  // one column twice
  EXPECT_THROW(parse_measurement_table("stature,165,cm\n"), Error);                    // a long set, not a table
  EXPECT_THROW(parse_measurement_table(""), Error);
}

}  // namespace
}  // namespace caliper
