// Typing mistakes in measurements (rules in the header).
#include "caliper/measure/input_check.h"

#include <cmath>
#include <iomanip>
#include <optional>
#include <sstream>

namespace caliper {

namespace {

constexpr double kInch = 2.54, kPound = 0.45359237;

std::string number(double v) {
  std::ostringstream s;
  const int decimals = std::abs(v - std::round(v)) < 0.05 ? 0 : std::abs(v) < 10 ? 2 : 1;
  s << std::fixed << std::setprecision(decimals) << v;
  return s.str();
}

// The words people use for the measurements a person types.
std::string words(const std::string& field) {
  static const std::map<std::string, std::string> names = {{"stature", "height"}, {"crotch_height", "inseam"},
      {"hip_breadth", "hip width"}, {"span", "arm span"}, {"arm_length", "arm length"}};
  auto it = names.find(field);
  return it == names.end() ? field : it->second;
}

double bmi(double stature_cm, double weight_kg) { return weight_kg / std::pow(stature_cm / 100, 2); }
bool adult_bmi(double b) { return b >= 14 && b <= 50; }
bool adult_height(double cm) { return cm >= 120 && cm <= 230; }

// A height typed in another unit: the conversion to cm that gives an adult height (and, when
// weight is given, an adult BMI).
std::optional<SuspectValue> height_unit(double cm, std::optional<double> kg) {
  if (adult_height(cm)) return std::nullopt;
  const struct { double factor; const char* unit; } units[] = {{100, "metres"}, {0.1, "millimetres"}, {kInch, "inches"}};
  for (const auto& u : units) {
    const double meant = cm * u.factor;
    if (!adult_height(meant) || (kg && !adult_bmi(bmi(meant, *kg)))) continue;
    return SuspectValue{"stature", cm, meant, "height " + number(cm) + " looks like " + u.unit + ": " + number(meant) + " cm"};
  }
  return std::nullopt;
}

// Lengths relative to stature, far outside any adult (ANSUR II's extremes lie well inside).
struct Proportion {
  const char* name;
  const char* words;
  double lo, hi;  // value / stature
};
const Proportion kProportions[] = {
    {"span", "arm span", 0.8, 1.25}, {"crotch_height", "inseam", 0.35, 0.6},
    {"arm_length", "arm length", 0.25, 0.45}, {"hip_breadth", "hip width", 0.14, 0.32}};

std::optional<SuspectValue> length_unit(const Proportion& p, double cm, double stature_cm) {
  const double ratio = cm / stature_cm;
  if (ratio >= p.lo && ratio <= p.hi) return std::nullopt;
  const struct { double factor; const char* unit; } units[] = {{kInch, "inches"}, {0.1, "millimetres"}, {100, "metres"}};
  for (const auto& u : units) {
    const double meant = cm * u.factor, r = meant / stature_cm;
    if (r < p.lo || r > p.hi) continue;
    return SuspectValue{p.name, cm, meant,
                        std::string(p.words) + " " + number(cm) + " is " + number(100 * ratio) + " % of the height; in " +
                            u.unit + " it would be " + number(meant) + " cm"};
  }
  return std::nullopt;
}

}  // namespace

std::vector<SuspectValue> suspect_input_mistakes(const std::map<std::string, double>& v) {
  std::vector<SuspectValue> out;
  auto get = [&](const char* name) -> std::optional<double> {
    auto it = v.find(name);
    if (it == v.end() || !std::isfinite(it->second)) return std::nullopt;
    return it->second;
  };
  std::optional<double> cm = get("stature"), kg = get("weight");
  // Swapped: a "height" that is an adult weight and a "weight" that is an adult height.
  if (cm && kg && !adult_height(*cm) && adult_height(*kg) && *cm >= 30 && adult_bmi(bmi(*kg, *cm))) {
    const std::string both = "height " + number(*cm) + " cm and weight " + number(*kg) + " kg look swapped";
    out.push_back({"stature", *cm, *kg, both});
    out.push_back({"weight", *kg, *cm, both});
    return out;  // the rest is judged once the user has answered
  }
  if (cm) {
    if (auto s = height_unit(*cm, kg)) {
      out.push_back(*s);
      cm = s->suggested;
    }
  }
  // Pounds: a weight no adult of this height has, that in kilograms would be an ordinary one.
  if (cm && kg && adult_height(*cm) && bmi(*cm, *kg) > 50 && adult_bmi(bmi(*cm, *kg * kPound)) && bmi(*cm, *kg * kPound) >= 16)
    out.push_back({"weight", *kg, *kg * kPound,
                   "weight " + number(*kg) + " kg at height " + number(*cm) + " cm looks like pounds: " + number(*kg * kPound) + " kg"});
  if (cm && adult_height(*cm))
    for (const Proportion& p : kProportions)
      if (auto len = get(p.name))
        if (auto s = length_unit(p, *len, *cm)) out.push_back(*s);
  return out;
}

std::map<std::string, double> apply_suggestions(std::map<std::string, double> values, const std::vector<SuspectValue>& suspects) {
  for (const auto& s : suspects) values[s.field] = s.suggested;
  return values;
}

std::string describe_suspects(const std::vector<SuspectValue>& suspects) {
  std::ostringstream m;
  std::string last_reason;
  for (const auto& s : suspects) {
    if (s.reason == last_reason) continue;  // a swap is one reason for two fields
    m << (m.tellp() > 0 ? "; " : "") << s.reason;
    last_reason = s.reason;
  }
  m << ". Did you mean";
  for (size_t i = 0; i < suspects.size(); ++i)
    m << (i ? ", " : " ") << words(suspects[i].field) << " " << number(suspects[i].suggested) << (suspects[i].field == "weight" ? " kg" : " cm");
  m << "? Use --force (API: \"force\": true) to build with the values as given";
  return m.str();
}

SuspectInputError::SuspectInputError(std::vector<SuspectValue> suspects)
    : Error(ErrorKind::InvalidArgument, describe_suspects(suspects), suspects.empty() ? "" : suspects.front().field),
      suspects_(std::move(suspects)) {}

}  // namespace caliper
