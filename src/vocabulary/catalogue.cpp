#include "caliper/vocabulary/catalogue.h"

#include <cctype>
#include <cmath>
#include <sstream>

#include "caliper/errors.h"

namespace caliper {

namespace {

// Accepted ranges at the edges are wide enough for any adult and many children (ANSUR II spans
// e.g. stature 141–199 cm), narrow enough to catch unit mistakes (mm or m typed for cm).
MeasurementInfo length(std::string name, double lo, double hi, std::vector<std::string> aliases,
                       std::string ansur, std::string label, bool paper = false) {
  return {std::move(name), Unit::Metre, lo, hi, std::move(aliases), std::move(ansur), std::move(label), paper};
}

}  // namespace

const std::vector<MeasurementInfo>& measurement_catalogue() {
  static const std::vector<MeasurementInfo> catalogue = {
      // The Virtual Caliper inputs (paper §3.1) first, in the paper's hierarchy.
      length("stature", 50, 250, {"height", "overall_height"}, "stature", "Stature (floor to top of head)", true),
      {"weight", Unit::Kilogram, 10, 300, {"mass", "body_mass"}, "weightkg", "Body weight", true},
      length("span", 50, 260, {"arm_span", "armspan", "arm_span_fingers"}, "span", "Arm span, fingertip to fingertip", true),
      length("crotch_height", 20, 130, {"inseam", "inseam_height"}, "crotchheight", "Inseam height (floor to crotch)", true),
      length("hip_breadth", 15, 80, {"hip_width"}, "hipbreadth", "Hip breadth, standing", true),
      length("arm_length", 20, 100, {"arm_length_shoulder_wrist"}, "acromionradialelength+radialestylionlength",
             "Arm length, acromion to wrist (stylion)", true),
      // The paper's other seven candidates.
      length("chest_height", 40, 200, {"nipple_height"}, "chestheight", "Chest height (floor to nipple / bust point)", true),
      length("waist_height", 30, 160, {"navel_height", "waist_height_omphalion"}, "waistheightomphalion", "Waist height at the navel (omphalion)", true),
      length("biacromial_breadth", 15, 70, {"shoulder_width"}, "biacromialbreadth", "Shoulder width, acromion to acromion", true),
      length("chest_breadth", 10, 70, {"chest_width"}, "chestbreadth", "Chest breadth at nipple height, across the front (between the arms)", true),
      length("waist_breadth", 10, 80, {"waist_width"}, "waistbreadth", "Waist breadth at navel height", true),
      length("waist_depth", 8, 70, {"torso_depth"}, "waistdepth", "Waist (torso) depth at navel height", true),
      length("wrist_span", 40, 230, {"arm_span_wrists"}, "", "Arm span, wrist to wrist", true),
      length("forearm_length", 10, 60, {}, "radialestylionlength", "Forearm length, elbow (radiale) to wrist (stylion)", true),
      // Further heights, breadths and depths.
      length("cervicale_height", 40, 220, {}, "cervicaleheight", "Cervicale height (floor to C7)"),
      length("acromial_height", 40, 210, {"shoulder_height"}, "acromialheight", "Acromial (shoulder) height"),
      length("axilla_height", 40, 200, {}, "axillaheight", "Axilla (armpit) height"),
      length("iliocristale_height", 30, 160, {}, "iliocristaleheight", "Iliac crest height"),
      length("trochanterion_height", 25, 140, {}, "trochanterionheight", "Trochanterion height"),
      length("buttock_height", 25, 140, {}, "buttockheight", "Buttock height"),
      length("knee_height", 15, 80, {"knee_height_midpatella"}, "kneeheightmidpatella", "Knee height, mid-patella"),
      length("lateral_malleolus_height", 2, 20, {"ankle_height"}, "lateralmalleolusheight", "Ankle (lateral malleolus) height"),
      length("chest_depth", 8, 70, {}, "chestdepth", "Chest depth at nipple height"),
      length("buttock_depth", 8, 70, {}, "buttockdepth", "Buttock depth"),
      length("upper_arm_length", 10, 60, {"acromion_radiale_length"}, "acromionradialelength", "Upper arm, acromion to radiale"),
      length("hand_length", 5, 35, {}, "handlength", "Hand length, wrist crease to middle fingertip"),
      length("hand_breadth", 3, 20, {}, "handbreadth", "Hand breadth at the knuckles"),
      length("foot_length", 8, 40, {}, "footlength", "Foot length, heel to longest toe"),
      length("foot_breadth", 3, 20, {}, "footbreadthhorizontal", "Foot breadth"),
      length("head_breadth", 8, 25, {}, "headbreadth", "Head breadth"),
      length("head_length", 10, 30, {}, "headlength", "Head length, glabella to back of head"),
      // Circumferences: a tape around a plane section (convex hull).
      length("chest_circumference", 40, 200, {"bust", "bust_circumference"}, "chestcircumference", "Chest (bust) circumference at nipple height"),
      length("waist_circumference", 35, 200, {"waist"}, "waistcircumference", "Waist circumference at the navel"),
      length("buttock_circumference", 40, 200, {"hip_circumference", "hips"}, "buttockcircumference", "Buttock (hip) circumference"),
      length("thigh_circumference", 20, 120, {"thigh"}, "thighcircumference", "Thigh circumference at the gluteal furrow"),
      length("lower_thigh_circumference", 15, 90, {}, "lowerthighcircumference", "Lower thigh circumference above the knee"),
      length("calf_circumference", 15, 80, {"calf"}, "calfcircumference", "Calf circumference"),
      length("ankle_circumference", 10, 50, {}, "anklecircumference", "Ankle circumference"),
      length("neck_circumference", 20, 70, {"neck"}, "neckcircumference", "Neck circumference"),
      length("head_circumference", 30, 80, {}, "headcircumference", "Head circumference"),
      length("biceps_circumference", 10, 70, {"upper_arm_circumference"}, "", "Upper arm (biceps) circumference, relaxed"),
      length("forearm_circumference", 10, 60, {}, "", "Forearm circumference, relaxed"),
      length("wrist_circumference", 8, 35, {"wrist"}, "wristcircumference", "Wrist circumference"),
  };
  return catalogue;
}

namespace {
std::string normalise(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '-' || c == ' ') out += '_';
    else out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  return out;
}
}  // namespace

const MeasurementInfo* find_measurement_info(const std::string& name_or_alias) {
  const std::string key = normalise(name_or_alias);
  for (const auto& info : measurement_catalogue()) {
    if (info.name == key) return &info;
    for (const auto& a : info.aliases)
      if (a == key) return &info;
  }
  return nullptr;
}

const char* edge_unit(const MeasurementInfo& info) { return info.unit == Unit::Kilogram ? "kg" : "cm"; }

double edge_to_si(const MeasurementInfo& info, double edge_value) {
  // Messages are built with a stream: GCC 12 warns (-Wrestrict, falsely) on long operator+ chains.
  std::ostringstream range;
  range << "[" << info.min_edge << ", " << info.max_edge << "] " << edge_unit(info);
  if (!std::isfinite(edge_value)) {
    std::ostringstream msg;
    msg << info.name << " must be a finite number in " << range.str() << " (got " << edge_value << ")";
    throw Error(ErrorKind::InvalidArgument, msg.str(), info.name);
  }
  if (edge_value < info.min_edge || edge_value > info.max_edge) {
    std::ostringstream msg;
    msg << info.name << " = " << edge_value << " " << edge_unit(info) << " is outside the accepted range " << range.str();
    throw Error(ErrorKind::OutOfRange, msg.str(), info.name);
  }
  return info.unit == Unit::Kilogram ? edge_value : edge_value / 100.0;
}

std::string edge_text(const std::string& name, double value_si) {
  const MeasurementInfo* info = find_measurement_info(name);
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(1);
  if (info) s << si_to_edge(*info, value_si) << " " << edge_unit(*info);
  else s << value_si * 100 << " cm";
  return s.str();
}

double si_to_edge(const MeasurementInfo& info, double value_si) {
  return info.unit == Unit::Kilogram ? value_si : value_si * 100.0;
}

}  // namespace caliper
