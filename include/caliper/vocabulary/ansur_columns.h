// The ANSUR II columns Caliper reads, by Caliper's measurement names (public format:
// ../shared/data/ansur2/README.md; column names lower-case). The catalogue (catalogue.h) gives
// each measurement's own column; this is what the CSV reader and the evaluation add to it.
#pragma once
#include <string>
#include <utility>
#include <vector>

namespace caliper {

// The six Virtual Caliper inputs and the columns whose sum each one is (arm_length =
// acromion–radiale + radiale–stylion length).
struct AnsurInputColumns {
  std::string measurement;           // e.g. "crotch_height"
  std::vector<std::string> columns;  // e.g. {"crotchheight"}
};
const std::vector<AnsurInputColumns>& virtual_caliper_input_columns();

// ANSUR II columns held out from the inputs and compared with the avatars, with the
// model measurement each corresponds to.
const std::vector<std::pair<std::string, std::string>>& held_out_columns();  // (ansur column, measurement)

// SI value of a raw ANSUR number for a column (mm → m; weightkg/10 → kg; interpupillary /10 mm).
double ansur_to_si(const std::string& column, double raw);

}  // namespace caliper
