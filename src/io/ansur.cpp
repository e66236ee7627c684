#include "caliper/io/ansur.h"

#include <cctype>
#include <charconv>
#include <fstream>
#include <set>
#include <sstream>

#include "caliper/errors.h"
#include "gate.h"
#include "caliper/vocabulary/catalogue.h"

namespace caliper {

namespace {
std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}
const std::set<std::string>& text_columns() {
  static const std::set<std::string> cols = {"gender", "date", "installation", "component", "branch", "primarymos",
                                             "subjectsbirthlocation", "subjectnumericrace", "ethnicity", "dodrace",
                                             "age", "heightin", "weightlbs", "writingpreference", "subjectid"};
  return cols;
}
std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  size_t start = 0;
  for (;;) {
    size_t comma = line.find(',', start);
    out.push_back(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

// The Virtual Caliper inputs a row provides, each within the catalogue's accepted range: a file
// in centimetres instead of ANSUR's millimetres would otherwise give 17 cm avatars without a word.
void check_inputs(const AnsurSubject& s, const std::string& where) {
  for (const auto& [name, columns] : virtual_caliper_input_columns()) {
    double si = 0;
    bool present = true;
    for (const std::string& c : columns) {
      auto it = s.values.find(c);
      if (it == s.values.end()) present = false;
      else si += it->second;
    }
    if (!present) continue;
    const MeasurementInfo* info = find_measurement_info(name);
    try {
      edge_to_si(*info, si_to_edge(*info, si));
    } catch (const Error& e) {
      throw Error(ErrorKind::OutOfRange, where + ": " + e.what() + " (ANSUR II files give lengths in millimetres and " +
                                             "weightkg in tenths of a kilogram)", columns.front());
    }
  }
}

}  // namespace

namespace {
// The reader itself; the public function below is its gate.
std::vector<AnsurSubject> parse_rows(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  std::string line;
  std::vector<std::string> header;
  std::vector<AnsurSubject> subjects;
  int line_no = 0, gender_col = -1, id_col = -1, age_col = -1;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    auto cells = split(line);
    if (header.empty()) {
      for (auto& c : cells) header.push_back(lower(c));
      for (size_t i = 0; i < header.size(); ++i) {
        if (header[i] == "gender") gender_col = static_cast<int>(i);
        if (header[i] == "subjectid") id_col = static_cast<int>(i);
        if (header[i] == "age") age_col = static_cast<int>(i);
      }
      bool has_stature = false;
      for (auto& h : header) has_stature |= h == "stature";
      if (!has_stature) throw Error(ErrorKind::Format, source + ":1: no 'stature' column: not an ANSUR II file", "stature");
      if (gender_col < 0) throw Error(ErrorKind::Format, source + ":1: no 'Gender' column", "gender");
      continue;
    }
    if (cells.size() != header.size())
      throw Error(ErrorKind::Format, source + ":" + std::to_string(line_no) + ": " + std::to_string(cells.size()) +
                                         " fields, the header has " + std::to_string(header.size()),
                  "line " + std::to_string(line_no));
    AnsurSubject s;
    s.id = id_col >= 0 ? cells[static_cast<size_t>(id_col)] : std::to_string(line_no);
    const std::string g = lower(cells[static_cast<size_t>(gender_col)]);
    if (g == "male") s.sex = Sex::Male;
    else if (g == "female") s.sex = Sex::Female;
    else throw Error(ErrorKind::Format, source + ":" + std::to_string(line_no) + ": Gender must be Male or Female", "gender");
    if (age_col >= 0) {
      const std::string& cell = cells[static_cast<size_t>(age_col)];
      double years = 0;
      const auto res = std::from_chars(cell.data(), cell.data() + cell.size(), years);
      if (res.ec == std::errc() && res.ptr == cell.data() + cell.size() && years > 0 && years < 150) s.age_years = years;
    }
    for (size_t i = 0; i < header.size(); ++i) {
      if (text_columns().count(header[i])) continue;
      const std::string& cell = cells[i];
      double v = 0;
      const auto res = std::from_chars(cell.data(), cell.data() + cell.size(), v);
      if (cell.empty() || res.ec != std::errc() || res.ptr != cell.data() + cell.size())
        throw Error(ErrorKind::Format, source + ":" + std::to_string(line_no) + ": column '" + header[i] +
                                           "' is not a number ('" + cell + "')", header[i]);
      s.values[header[i]] = ansur_to_si(header[i], v);
    }
    check_inputs(s, source + ":" + std::to_string(line_no));
    subjects.push_back(std::move(s));
  }
  if (header.empty()) throw Error(ErrorKind::Format, source + ": empty file", "header");
  return subjects;
}
}  // namespace

std::vector<AnsurSubject> parse_ansur_csv(const std::string& text, const std::string& source) {
  return gate(source, "header", [&] { return parse_rows(text, source); });
}

std::vector<AnsurSubject> read_ansur_csv(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error(ErrorKind::Io, "cannot open '" + path + "'", path);
  std::ostringstream ss;
  ss << f.rdbuf();
  return parse_ansur_csv(ss.str(), path);
}

std::map<std::string, double> virtual_caliper_inputs(const AnsurSubject& s) {
  std::map<std::string, double> out;
  for (const auto& [name, columns] : virtual_caliper_input_columns())
    for (const std::string& c : columns) {
      auto it = s.values.find(c);
      if (it == s.values.end()) throw Error(ErrorKind::Format, std::string("subject ") + s.id + " has no '" + c + "'", c);
      out[name] += it->second;
    }
  return out;
}

}  // namespace caliper
