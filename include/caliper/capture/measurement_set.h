// Measurement-set files: a person's values in centimetres and kilograms, the desktop tool's
// import/export format (docs/api.md "Measurement sets"). Capture exports them; `caliper avatar
// --measurements FILE` reads them.
//   JSON: {"format": "caliper-measurements", "version": 1, "sex": "female"|null, "model": null,
//          "measured_by": "self"|"other" (optional), "units": "lengths in cm, weight in kg",
//          "measurements": {"stature": 165, …}}
//   CSV, long:  measurement,value,unit / sex,female, / measured_by,self, / stature,165,cm …
//   CSV, wide:  a header of column names, one person per row (a set holds one row; a table any):
//               id,sex,height,weight,arm_span,… (names or aliases; a unit may follow a name:
//               stature_cm, "Weight (kg)"; else cm and kg), optional measured_by; blank cells are
//               values not measured
//   CSV, ANSUR II public layout (tables only): Gender, weightkg (tenths of kg), lengths in mm;
//               the six Virtual Caliper inputs are read
// Every CSV may be ';'-separated with decimal commas (European spreadsheets) or comma-separated
// with quoted decimal commas ("165,5"); the separator is detected from the first line.
// `measured_by` says who took the values (a capture session writes it): the estimator then
// weighs them with that setting's noise (paper Table 2) unless the user states another.
#pragma once
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "caliper/vocabulary/sex.h"

namespace caliper {

struct MeasurementSetFile {
  std::optional<Sex> sex;
  std::optional<std::string> measured_by;  // "self" or "other"
  std::optional<std::string> model;        // the body model the values were set on, when the file says
  std::map<std::string, double> edge;  // canonical name → cm or kg
};

// Written in catalogue order; values rounded to 0.1 mm / 0.1 g.
std::string write_measurement_set_json(const MeasurementSetFile& set);
std::string write_measurement_set_csv(const MeasurementSetFile& set);

// Reads either format (JSON if the text starts with '{'). Accepts aliases, a flat JSON object,
// a Caliper report (each entry's requested value; achieved-only entries were not inputs),
// units cm/mm/m/in and kg/g/lb in CSV. The one reader for every caller: CLI, server, capture. Throws Error(Format) for a malformed file and
// Error(InvalidArgument|OutOfRange) naming the measurement for a bad value. Errors about the set
// as a whole (empty, not JSON, a number beyond a double) name the field "measurements".
MeasurementSetFile parse_measurement_set(const std::string& text);

// A table of people (`caliper batch`): one row per person, wide or ANSUR II layout. Rows with a
// bad cell are left out and listed in `skipped` (line, field, and the reason with the accepted
// range); so are a participant id seen before and a row without measurements. Throws
// Error(Format) for a file that is not such a table (a header Caliper cannot read, an unknown
// column: the error lists the accepted names).
struct MeasurementRow {
  int line = 0;             // 1-based line in the file
  std::string participant;  // the id column ("" when the table has none)
  MeasurementSetFile set;
};
struct SkippedRow {
  int line = 0;
  std::string field;
  std::string reason;
};
struct MeasurementTable {
  std::string layout;  // "wide" or "ansur"
  std::vector<MeasurementRow> rows;
  std::vector<SkippedRow> skipped;
};
MeasurementTable parse_measurement_table(const std::string& text);
MeasurementTable read_measurement_table(const std::string& path);  // + Error(Io)

namespace capture { class CaptureProtocol; }
// A capture session's result as a measurement set: its settled values, sex and who measured.
MeasurementSetFile measurement_set_of(const capture::CaptureProtocol& session);
MeasurementSetFile read_measurement_set(const std::string& path);  // + Error(Io)

}  // namespace caliper
