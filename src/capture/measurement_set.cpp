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
#include "caliper/vocabulary/ansur_columns.h"
#include "caliper/vocabulary/catalogue.h"
#include "csv_table.h"
#include "gate.h"

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
  try {
    edge_to_si(*info, e);  // range check naming the field
  } catch (const Error& bad) {
    if (where.rfind("line ", 0) != 0) throw;
    throw bad.restated(where + ": " + bad.what(), bad.field());  // a table's row: say which
  }
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

// ---- CSV: the long layout (measurement,value,unit; one person), the wide layout (a header of
// measurement names, one person per row, cm/kg) and the ANSUR II layout (mm, tenths of kg).

std::string where_line(int line) { return "line " + std::to_string(line); }

// A cell's number, or Error(Format) naming the line and the field, with a hint for the usual
// spreadsheet habits (a unit typed into the cell, a decimal comma in a comma-separated file).
double cell_number(const std::string& cell, const std::string& field, int line) {
  if (const auto v = detail::parse_decimal(cell)) return *v;
  std::string hint;
  const std::string t = lower_trim(cell);
  if (!t.empty() && std::isdigit(static_cast<unsigned char>(t[0])) && std::isalpha(static_cast<unsigned char>(t.back())))
    hint = " (write the number alone: centimetres and kilograms are implied, or put the unit in its own column)";
  throw Error(ErrorKind::Format, where_line(line) + ": the value of " + field + " is not a number ('" + cell + "')" + hint,
              field);
}

MeasurementSetFile parse_long(const detail::CsvText& csv) {
  MeasurementSetFile set;
  for (const auto& [line, cells] : csv.lines) {
    const std::string where = where_line(line);
    const std::string first = lower_trim(cells[0]);
    if (first == "measurement" || first == "name") continue;
    const std::string second = cells.size() >= 2 ? cells[1] : "";
    if (first == "model") {
      if (!trim(second).empty()) set.model = trim(second);
      continue;
    }
    if (first == "sex" || first == "measured_by") {
      if (trim(second).empty()) throw Error(ErrorKind::Format, where + ": " + first + " needs a value", first);
      if (first == "sex") set.sex = sex_of(second, where);
      else set.measured_by = measurer_of(second, where);
      continue;
    }
    if (cells.size() < 2) throw Error(ErrorKind::Format, where + ": expected measurement,value[,unit]", first);
    if (cells.size() > 3)
      throw Error(ErrorKind::Format,
                  where + ": " + std::to_string(cells.size()) + " cells, expected measurement,value[,unit] (a decimal " +
                      "comma must be quoted, \"165,5\", or the cells separated by ';')",
                  first);
    add(set, first, cell_number(second, first, line), cells.size() >= 3 ? cells[2] : "", where);
  }
  return set;
}

// What a wide table's column holds.
struct Column {
  enum Kind { Measurement, Participant, SexColumn, MeasuredBy, Ignored } kind = Ignored;
  const MeasurementInfo* info = nullptr;  // Measurement
  std::string unit;                       // from the header ("stature_cm", "Weight (kg)"), empty: cm / kg
  std::string header;                     // as written
};

// Header words people use for the participant's id, and columns a spreadsheet often carries
// that say nothing about the body.
bool is_participant_header(const std::string& h) {
  for (const char* n : {"id", "participant", "participant_id", "participantid", "subject", "subject_id", "subjectid",
                        "pid", "code", "person"})
    if (h == n) return true;
  return false;
}
bool is_ignored_header(const std::string& h) {
  for (const char* n : {"notes", "note", "comment", "comments", "date", "time", "age", "session"})
    if (h == n) return true;
  return false;
}

// "Arm span (cm)", "weight_kg", "Hip width [cm]" → ("arm_span", "cm").
std::pair<std::string, std::string> header_name_and_unit(const std::string& header) {
  std::string h = lower_trim(header), unit;
  if (const size_t open = h.find_first_of("(["); open != std::string::npos && (h.back() == ')' || h.back() == ']')) {
    unit = lower_trim(h.substr(open + 1, h.size() - open - 2));
    h = lower_trim(h.substr(0, open));
  }
  for (auto& c : h)
    if (c == ' ' || c == '-' || c == '.') c = '_';
  if (unit.empty() && !find_measurement_info(h))
    for (const char* u : {"cm", "mm", "m", "in", "kg", "g", "lb", "lbs"}) {
      const std::string suffix = std::string("_") + u;
      if (h.size() > suffix.size() && h.compare(h.size() - suffix.size(), suffix.size(), suffix) == 0 &&
          find_measurement_info(h.substr(0, h.size() - suffix.size()))) {
        unit = u;
        h = h.substr(0, h.size() - suffix.size());
        break;
      }
    }
  return {h, unit};
}

Column column_of(const std::string& header) {
  const auto [name, unit] = header_name_and_unit(header);
  Column c;
  c.header = header;
  c.unit = unit;
  if (const MeasurementInfo* info = find_measurement_info(name)) {
    c.kind = Column::Measurement;
    c.info = info;
  } else if (is_participant_header(name)) c.kind = Column::Participant;
  else if (name == "sex" || name == "gender") c.kind = Column::SexColumn;
  else if (name == "measured_by") c.kind = Column::MeasuredBy;
  else if (is_ignored_header(name)) c.kind = Column::Ignored;
  else
    throw Error(ErrorKind::Format,
                "line 1: column '" + header + "' is neither a measurement Caliper knows (stature or height, weight, " +
                    "span or arm_span, crotch_height or inseam, hip_breadth or hip_width, arm_length, … as `caliper " +
                    "model info` lists them; units may follow: stature_cm, \"Weight (kg)\") nor id, sex or " +
                    "measured_by: rename or remove it",
                header);
  return c;
}

// A wide header: not the long layout's, and its second cell names a column (in the long layout
// the second cell is a value: "stature,165", "sex,female").
bool is_wide_header(const detail::CsvLine& line) {
  if (line.cells.size() < 2) return false;
  const std::string first = lower_trim(line.cells[0]);
  if (first == "measurement" || first == "name") return false;
  const std::string second = header_name_and_unit(line.cells[1]).first;
  return find_measurement_info(second) || is_participant_header(second) || second == "sex" || second == "gender" ||
         second == "measured_by" || is_ignored_header(second);
}

// The ANSUR II public layout: its Gender and weightkg columns (Caliper's own names are sex and weight).
bool is_ansur_header(const detail::CsvLine& line) {
  bool gender = false, weightkg = false;
  for (const auto& c : line.cells) {
    gender |= lower_trim(c) == "gender";
    weightkg |= lower_trim(c) == "weightkg";
  }
  return gender && weightkg;
}

// One wide row → a person; throws Error naming the line and the field for a bad cell.
MeasurementRow wide_row(const std::vector<Column>& columns, const detail::CsvLine& line) {
  MeasurementRow row;
  row.line = line.number;
  const std::string where = where_line(line.number);
  if (line.cells.size() > columns.size())
    throw Error(ErrorKind::Format,
                where + ": " + std::to_string(line.cells.size()) + " cells, the header has " +
                    std::to_string(columns.size()) + " (a decimal comma must be quoted, \"165,5\", or the cells " +
                    "separated by ';')",
                "line");
  for (size_t i = 0; i < line.cells.size(); ++i) {
    const std::string& cell = line.cells[i];
    if (trim(cell).empty()) continue;  // a blank cell: not measured
    const Column& c = columns[i];
    switch (c.kind) {
      case Column::Measurement: add(row.set, c.info->name, cell_number(cell, c.info->name, line.number), c.unit, where); break;
      case Column::Participant: row.participant = trim(cell); break;
      case Column::SexColumn: row.set.sex = sex_of(cell, where); break;
      case Column::MeasuredBy: row.set.measured_by = measurer_of(cell, where); break;
      case Column::Ignored: break;
    }
  }
  if (row.set.edge.empty()) throw Error(ErrorKind::Format, where + ": no measurements in this row", "measurements");
  return row;
}

// One ANSUR II row → a person's Virtual Caliper inputs (mm and tenths of kg → cm and kg).
MeasurementRow ansur_row(const std::vector<std::string>& header, const detail::CsvLine& line) {
  MeasurementRow row;
  row.line = line.number;
  const std::string where = where_line(line.number);
  if (line.cells.size() != header.size())
    throw Error(ErrorKind::Format,
                where + ": " + std::to_string(line.cells.size()) + " cells, the header has " + std::to_string(header.size()),
                "line");
  auto cell_of = [&](const std::string& column) -> const std::string* {
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == column) return &line.cells[i];
    return nullptr;
  };
  if (const std::string* id = cell_of("subjectid")) row.participant = trim(*id);
  row.set.sex = sex_of(*cell_of("gender"), where);
  for (const auto& [name, cols] : virtual_caliper_input_columns()) {
    double si = 0;
    bool present = true;
    for (const std::string& col : cols) {
      const std::string* cell = cell_of(col);
      if (!cell || trim(*cell).empty()) present = false;
      else si += ansur_to_si(col, cell_number(*cell, col, line.number));
    }
    if (!present) continue;
    const MeasurementInfo* info = find_measurement_info(name);
    try {
      add(row.set, name, si_to_edge(*info, si), "", where);
    } catch (const Error& e) {
      throw Error(e.kind(), std::string(e.what()) + " (ANSUR II files give lengths in millimetres and weightkg in tenths "
                                                    "of a kilogram)", name);
    }
  }
  if (row.set.edge.empty()) throw Error(ErrorKind::Format, where + ": no measurements in this row", "measurements");
  return row;
}

MeasurementTable parse_table(const detail::CsvText& csv) {
  MeasurementTable table;
  if (csv.lines.empty()) throw Error(ErrorKind::Format, "the table is empty", "measurements");
  const detail::CsvLine& head = csv.lines.front();
  std::vector<Column> columns;
  std::vector<std::string> ansur_header;
  if (is_ansur_header(head)) {
    table.layout = "ansur";
    for (const auto& c : head.cells) ansur_header.push_back(lower_trim(c));
  } else if (is_wide_header(head)) {
    table.layout = "wide";
    for (const auto& h : head.cells) columns.push_back(column_of(h));
    for (size_t i = 0; i < columns.size(); ++i)
      for (size_t k = 0; k < i; ++k)
        if (columns[i].kind != Column::Ignored && columns[i].kind == columns[k].kind && columns[i].info == columns[k].info)
          throw Error(ErrorKind::Format, "line 1: columns '" + columns[k].header + "' and '" + columns[i].header +
                                             "' are the same", columns[i].header);
  } else {
    throw Error(ErrorKind::Format,
                "line " + std::to_string(head.number) + ": not a table of people: the first line must name the " +
                    "columns (id,sex,height,weight,…) as in docs/cli.md, or be an ANSUR II header",
                "header");
  }
  std::map<std::string, int> line_of_participant;
  for (size_t r = 1; r < csv.lines.size(); ++r) {
    const detail::CsvLine& line = csv.lines[r];
    try {
      MeasurementRow row = table.layout == "ansur" ? ansur_row(ansur_header, line) : wide_row(columns, line);
      if (!row.participant.empty()) {
        const auto [it, fresh] = line_of_participant.emplace(row.participant, row.line);
        if (!fresh)
          throw Error(ErrorKind::Format, where_line(row.line) + ": participant '" + row.participant +
                                             "' is already on line " + std::to_string(it->second), "id");
      }
      table.rows.push_back(std::move(row));
    } catch (const Error& e) {
      table.skipped.push_back({line.number, e.field(), e.what()});
    }
  }
  return table;
}

MeasurementSetFile parse_csv(const std::string& text) {
  const detail::CsvText csv = detail::split_csv(text, "measurement set");
  if (csv.lines.empty() || !(is_wide_header(csv.lines.front()) || is_ansur_header(csv.lines.front())))
    return parse_long(csv);
  // A table of one person: its row is the set; a bad cell is an error, not a skipped row.
  MeasurementTable table = parse_table(csv);
  if (!table.skipped.empty()) {
    const SkippedRow& bad = table.skipped.front();
    throw Error(ErrorKind::Format, bad.reason, bad.field);
  }
  if (table.rows.size() != 1)
    throw Error(ErrorKind::Format,
                "a measurement set holds one person; this table has " + std::to_string(table.rows.size()) +
                    " rows (`caliper batch --subjects FILE` makes one avatar per row)",
                "measurements");
  return table.rows.front().set;
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

MeasurementTable parse_measurement_table(const std::string& text) {
  return gate("measurement table", "measurements", [&] { return parse_table(detail::split_csv(text, "measurement table")); });
}

MeasurementTable read_measurement_table(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorKind::Io, "cannot read '" + path + "'", path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_measurement_table(ss.str());
}

MeasurementSetFile read_measurement_set(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorKind::Io, "cannot read measurement set '" + path + "'", path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_measurement_set(ss.str());
}

}  // namespace caliper
