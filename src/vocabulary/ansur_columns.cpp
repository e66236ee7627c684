#include "caliper/vocabulary/ansur_columns.h"

#include <cctype>

namespace caliper {

const std::vector<AnsurInputColumns>& virtual_caliper_input_columns() {
  static const std::vector<AnsurInputColumns> columns = {
      {"stature", {"stature"}},           {"weight", {"weightkg"}},        {"span", {"span"}},
      {"crotch_height", {"crotchheight"}}, {"hip_breadth", {"hipbreadth"}}, {"arm_length", {"acromionradialelength", "radialestylionlength"}}};
  return columns;
}

const std::vector<std::pair<std::string, std::string>>& held_out_columns() {
  static const std::vector<std::pair<std::string, std::string>> cols = {
      {"chestcircumference", "chest_circumference"}, {"waistcircumference", "waist_circumference"},
      {"buttockcircumference", "buttock_circumference"}, {"thighcircumference", "thigh_circumference"},
      {"calfcircumference", "calf_circumference"}, {"biacromialbreadth", "biacromial_breadth"},
      {"chestbreadth", "chest_breadth"}, {"chestdepth", "chest_depth"}, {"waistbreadth", "waist_breadth"},
      {"waistdepth", "waist_depth"}, {"acromialheight", "acromial_height"}, {"waistheightomphalion", "waist_height"}};
  return cols;
}

double ansur_to_si(const std::string& column, double raw) {
  std::string c = column;
  for (auto& ch : c) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  if (c == "weightkg") return raw / 10.0;
  if (c == "interpupillarybreadth") return raw / 10000.0;
  return raw / 1000.0;
}

}  // namespace caliper
