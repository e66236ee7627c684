// Measurement-set files (docs/api.md "Measurement sets"), for capture exports and
// `caliper avatar --measurements`.
#include "caliper/capture/measurement_set.h"
#include "caliper/capture/protocol.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "caliper/errors.h"
#include "gate.h"
#include "caliper/vocabulary/catalogue.h"

namespace caliper {

namespace {

// A cell without surrounding blanks and quotes (spreadsheets quote cells).
std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r\n\"");
  if (a == std::string::npos) return {};
  return s.substr(a, s.find_last_not_of(" \t\r\n\"") - a + 1);
}

std::string lower_trim(const std::string& s) {
  std::string t = trim(s);
  for (auto& c : t) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return t;
}

// Divides by the integer 1/step so 172.3 prints as 172.3, not 172.30000000000001.
double round_to(double v, double step) {
  const double inverse = std::round(1.0 / step);
  return std::round(v * inverse) / inverse;
}

std::string number(double v) {
  std::ostringstream os;
  os.precision(10);
  os << round_to(v, 1e-4);
  return os.str();
}

double to_edge(const MeasurementInfo& info, double v, const std::string& unit_text, const std::string& where) {
  const std::string unit = lower_trim(unit_text);
  if (unit.empty()) return v;
  if (info.unit == Unit::Kilogram) {
    if (unit == "kg") return v;
    if (unit == "g") return v / 1000;
    if (unit == "lb" || unit == "lbs") return v * 0.45359237;
  } else {
    if (unit == "cm") return v;
    if (unit == "mm") return v / 10;
    if (unit == "m") return v * 100;
    if (unit == "in" || unit == "inch") return v * 2.54;
  }
  throw Error(ErrorKind::Format,
              where + ": unit '" + unit_text + "' does not fit " + info.name +
                  (info.unit == Unit::Kilogram ? " (use kg, g or lb)" : " (use cm, mm, m or in)"),
              info.name);
}

void add(MeasurementSetFile& set, const std::string& name, double v, const std::string& unit, const std::string& where) {
  const MeasurementInfo* info = find_measurement_info(name);
  if (!info) throw Error(ErrorKind::Format, where + ": unknown measurement '" + name + "'", name);
  if (set.edge.count(info->name)) throw Error(ErrorKind::Format, where + ": " + info->name + " is given twice", info->name);
  const double e = to_edge(*info, v, unit, where);
  edge_to_si(*info, e);  // range check naming the field
  set.edge[info->name] = e;
}

Sex sex_of(const std::string& text, const std::string& where) {
  const std::string t = lower_trim(text);
  if (t == "female" || t == "f") return Sex::Female;
  if (t == "male" || t == "m") return Sex::Male;
  if (t == "neutral" || t == "n") return Sex::Neutral;  // as `--sex neutral` and the server allow
  throw Error(ErrorKind::Format, where + ": sex must be female, male or neutral (got '" + text + "')", "sex");
}

std::string measurer_of(const std::string& text, const std::string& where) {
  const std::string t = lower_trim(text);
  if (t == "self" || t == "other") return t;
  throw Error(ErrorKind::Format, where + ": measured_by must be self or other (got '" + text + "')", "measured_by");
}

// A Caliper report lists every measurement as {"requested_cm": …, "achieved_cm": …}: what was
// requested was an input; an entry with only an achieved value was not, and is skipped.
void add_report_entry(MeasurementSetFile& set, const std::string& name, const nlohmann::json& entry) {
  bool report_entry = false;
  for (const char* key : {"requested_cm", "requested_kg", "achieved_cm", "achieved_kg"}) {
    if (!entry.contains(key)) continue;
    report_entry = true;
    const auto& v = entry[key];
    if (std::string(key).rfind("requested", 0) != 0 || v.is_null()) continue;
    if (!v.is_number()) throw Error(ErrorKind::Format, "measurements." + name + "." + key + " must be a number", name);
    add(set, name, v.get<double>(), "", "measurements." + name);
  }
  if (!report_entry) throw Error(ErrorKind::Format, "measurements." + name + " must be a number (cm or kg)", name);
}

MeasurementSetFile parse_json(const std::string& text) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(ErrorKind::Format, std::string("measurement set: not valid JSON: ") + e.what(), "measurements");
  } catch (const nlohmann::json::out_of_range&) {
    throw Error(ErrorKind::Format, "measurement set: a number is too large (beyond ±1.8e308)", "measurements");
  }
  if (!j.is_object()) throw Error(ErrorKind::Format, "measurement set: expected a JSON object", "measurements");
  // A newer writer may mean something this reader does not know: refuse rather than guess.
  if (j.contains("version") && !(j["version"].is_number_integer() && j["version"].get<long long>() == 1))
    throw Error(ErrorKind::Format, "measurement set: version " + j["version"].dump() + " is not one this Caliper reads (1)",
                "version");
  MeasurementSetFile set;
  if (j.contains("sex") && j["sex"].is_string()) set.sex = sex_of(j["sex"].get<std::string>(), "sex");
  if (j.contains("model") && j["model"].is_string()) set.model = j["model"].get<std::string>();
  if (j.contains("measured_by") && !j["measured_by"].is_null()) {
    if (!j["measured_by"].is_string()) throw Error(ErrorKind::Format, "measured_by must be \"self\" or \"other\"", "measured_by");
    set.measured_by = measurer_of(j["measured_by"].get<std::string>(), "measured_by");
  }
  const bool nested = j.contains("measurements");
  const nlohmann::json& m = nested ? j["measurements"] : j;
  if (!m.is_object()) throw Error(ErrorKind::Format, "measurement set: measurements must be an object", "measurements");
  for (const auto& [name, value] : m.items()) {
    if (!nested && (name == "sex" || name == "model" || name == "format" || name == "version" || name == "units" ||
                    name == "warnings" || name == "measured_by"))
      continue;
    if (value.is_null()) continue;
    if (value.is_object()) {  // a Caliper report's entry
      add_report_entry(set, name, value);
      continue;
    }
    if (!value.is_number()) throw Error(ErrorKind::Format, "measurements." + name + " must be a number (cm or kg)", name);
    add(set, name, value.get<double>(), "", "measurements." + name);
  }
  return set;
}

MeasurementSetFile parse_csv(const std::string& text) {
  MeasurementSetFile set;
  std::stringstream ss(text);
  std::string line;
  int line_no = 0;
  while (std::getline(ss, line)) {
    ++line_no;
    if (line_no == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line = line.substr(3);
    const std::string t = lower_trim(line);
    if (t.empty() || t[0] == '#') continue;
    const char sep = line.find(',') != std::string::npos ? ',' : (line.find(';') != std::string::npos ? ';' : '\t');
    std::vector<std::string> cells;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, sep)) cells.push_back(cell);
    const std::string where = "line " + std::to_string(line_no);
    const std::string first = lower_trim(cells[0]);
    if (first == "measurement" || first == "name") continue;
    if (first == "model") {
      if (cells.size() >= 2 && !trim(cells[1]).empty()) set.model = trim(cells[1]);
      continue;
    }
    if (first == "sex") {
      if (cells.size() < 2) throw Error(ErrorKind::Format, where + ": sex needs a value", "sex");
      set.sex = sex_of(cells[1], where);
      continue;
    }
    if (first == "measured_by") {
      if (cells.size() < 2) throw Error(ErrorKind::Format, where + ": measured_by needs a value", "measured_by");
      set.measured_by = measurer_of(cells[1], where);
      continue;
    }
    if (cells.size() < 2) throw Error(ErrorKind::Format, where + ": expected measurement,value[,unit]", first);
    const std::string value = lower_trim(cells[1]);
    double v = 0;
    size_t used = 0;
    try {
      v = std::stod(value, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (value.empty() || used != value.size())
      throw Error(ErrorKind::Format, where + ": the value of " + first + " is not a number ('" + cells[1] + "')", first);
    add(set, first, v, cells.size() >= 3 ? cells[2] : "", where);
  }
  return set;
}

}  // namespace

std::string write_measurement_set_json(const MeasurementSetFile& set) {
  nlohmann::ordered_json j;
  j["format"] = "caliper-measurements";
  j["version"] = 1;
  j["sex"] = set.sex ? nlohmann::ordered_json(to_string(*set.sex)) : nlohmann::ordered_json(nullptr);
  j["model"] = set.model ? nlohmann::ordered_json(*set.model) : nlohmann::ordered_json(nullptr);
  if (set.measured_by) j["measured_by"] = *set.measured_by;
  j["units"] = "lengths in cm, weight in kg";
  nlohmann::ordered_json m = nlohmann::ordered_json::object();
  for (const auto& info : measurement_catalogue()) {
    auto it = set.edge.find(info.name);
    if (it != set.edge.end()) m[info.name] = round_to(it->second, 1e-4);
  }
  j["measurements"] = m;
  return j.dump(2) + "\n";
}

std::string write_measurement_set_csv(const MeasurementSetFile& set) {
  std::string out = "measurement,value,unit\n";
  if (set.sex) out += std::string("sex,") + to_string(*set.sex) + ",\n";
  if (set.model) out += "model," + *set.model + ",\n";
  if (set.measured_by) out += "measured_by," + *set.measured_by + ",\n";
  for (const auto& info : measurement_catalogue()) {
    auto it = set.edge.find(info.name);
    if (it != set.edge.end()) out += info.name + "," + number(it->second) + "," + edge_unit(info) + "\n";
  }
  return out;
}

namespace {
// The reader itself; the public function below is its gate.
MeasurementSetFile parse_either_format(const std::string& text) {
  const size_t a = text.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) throw Error(ErrorKind::Format, "the measurement set is empty", "measurements");
  // JSON if it looks like JSON (an array, too, gets the JSON reader's clear refusal), else CSV.
  MeasurementSetFile set = text[a] == '{' || text[a] == '[' ? parse_json(text) : parse_csv(text);
  if (set.edge.empty()) throw Error(ErrorKind::Format, "the measurement set has no measurements", "measurements");
  return set;
}
}  // namespace

MeasurementSetFile parse_measurement_set(const std::string& text) {
  return gate("measurement set", "measurements", [&] { return parse_either_format(text); });
}

MeasurementSetFile measurement_set_of(const capture::CaptureProtocol& session) {
  MeasurementSetFile set;
  set.sex = session.sex();
  set.edge = session.measurement_set();
  set.measured_by = capture::to_string(session.config().mode);
  return set;
}

MeasurementSetFile read_measurement_set(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorKind::Io, "cannot read measurement set '" + path + "'", path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_measurement_set(ss.str());
}

}  // namespace caliper
