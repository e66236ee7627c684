// Every measurement Caliper knows: names (ANSUR II where one exists), units, aliases,
// accepted input ranges at the user's edges, and the ANSUR II column it compares with.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace caliper {

enum class Unit { Metre, Kilogram };

struct MeasurementInfo {
  std::string name;                  // canonical, e.g. "crotch_height"
  Unit unit = Unit::Metre;
  double min_edge = 0, max_edge = 0; // accepted input range at the edges, in cm or kg
  std::vector<std::string> aliases;  // e.g. "inseam", "height"
  std::string ansur_column;          // e.g. "crotchheight"; empty if ANSUR has none
  std::string label;                 // human words: "Inseam height (floor to crotch)"
  bool paper_13 = false;             // one of the paper's 13 candidate measurements (or weight)
};

const std::vector<MeasurementInfo>& measurement_catalogue();
// Looks up a canonical name or alias (case-insensitive, '-' and '_' equivalent); nullptr if unknown.
const MeasurementInfo* find_measurement_info(const std::string& name_or_alias);

// Converts a user-edge value (cm or kg) to SI after checking it: throws Error(InvalidArgument)
// for NaN/inf and Error(OutOfRange) naming the field and the accepted range otherwise.
double edge_to_si(const MeasurementInfo& info, double edge_value);
double si_to_edge(const MeasurementInfo& info, double value_si);  // m → cm, kg → kg
const char* edge_unit(const MeasurementInfo& info);                // "cm" or "kg"
// An SI value of a named measurement as people read it, one decimal: "167.0 cm", "62.0 kg"
// (an unknown name is taken as a length).
std::string edge_text(const std::string& name, double value_si);

}  // namespace caliper
