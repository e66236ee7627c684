// Measurement sets (src/capture/measurement_set.cpp, parse_measurement_set): the JSON and CSV
// forms the CLI, the server's import and capture exports all read. Oracles: accepted values are
// finite; what the library writes (JSON and CSV) it reads back, and writing that again gives the
// same bytes (the writers round to 0.1 mm, so the first write may differ from the input).
// The same bytes as a table of people (parse_measurement_table, `caliper batch`): every row kept
// or skipped once, kept values finite, ids unique.
#include <cmath>
#include <set>

#include "caliper/capture/measurement_set.h"
#include "fuzz_support.h"

using namespace caliper;

namespace {

void round_trips(const MeasurementSetFile& set, std::string (*write)(const MeasurementSetFile&), const char* form) {
  const std::string once = write(set);
  MeasurementSetFile reread;
  fuzz::check(fuzz::accepts([&] { reread = parse_measurement_set(once); }),
              std::string("the library refuses its own ") + form + ":\n" + once);
  fuzz::check(reread.sex == set.sex && reread.measured_by == set.measured_by,
              std::string("sex or measured_by changed in a ") + form + " round trip");
  fuzz::check(write(reread) == once, std::string("a ") + form + " set changes when written again:\n" + once);
}

void check_table(const std::string& text) {
  MeasurementTable table;
  if (!fuzz::accepts([&] { table = parse_measurement_table(text); })) return;
  std::set<int> lines;
  std::set<std::string> ids;
  for (const auto& row : table.rows) {
    fuzz::check(lines.insert(row.line).second, "a table row is kept twice");
    fuzz::check(row.participant.empty() || ids.insert(row.participant).second, "a participant id is kept twice");
    for (const auto& [name, value] : row.set.edge) fuzz::check(std::isfinite(value), "non-finite table value for " + name);
  }
  for (const auto& s : table.skipped) fuzz::check(lines.insert(s.line).second, "a table row is both kept and skipped");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  check_table(fuzz::as_string(data, size));
  MeasurementSetFile set;
  if (!fuzz::accepts([&] { set = parse_measurement_set(fuzz::as_string(data, size)); })) return 0;
  for (const auto& [name, value] : set.edge) fuzz::check(std::isfinite(value), "non-finite value for " + name);
  round_trips(set, write_measurement_set_json, "JSON");
  round_trips(set, write_measurement_set_csv, "CSV");
  return 0;
}
