// ANSUR II anthropometry CSV files (public format; ../shared/data/ansur2/README.md): header
// names case-insensitive, Latin-1, CRLF or LF, last line with or without newline, lengths in
// mm, `weightkg` in tenths of kg, `interpupillarybreadth` in tenths of mm, sex from `Gender`.
#pragma once
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "caliper/vocabulary/ansur_columns.h"  // ansur_to_si, the input and held-out columns
#include "caliper/vocabulary/sex.h"

namespace caliper {

struct AnsurSubject {
  std::string id;
  Sex sex = Sex::Neutral;
  std::map<std::string, double> values;  // lowercase column → value in SI (m, kg)
  double age_years = std::nan("");        // the Age column, if present (describes the population)
};

// Reads every row. Numeric columns are converted to SI; text columns other than Gender and the
// id are ignored. Throws Error(Io) if unreadable, Error(Format) naming line and column for a
// ragged row, a non-numeric measurement or a missing Gender/stature column.
std::vector<AnsurSubject> read_ansur_csv(const std::string& path);
std::vector<AnsurSubject> parse_ansur_csv(const std::string& text, const std::string& source_name);

// The six Virtual Caliper inputs of a subject, by Caliper's canonical names, SI:
// stature, weight, span, crotch_height, hip_breadth, arm_length (acromion–radiale + radiale–stylion).
std::map<std::string, double> virtual_caliper_inputs(const AnsurSubject& subject);

}  // namespace caliper
