// Body-image tasks: the words and the checks of what a client may start or answer.
#include "caliper/capture/body_image_task.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "caliper/errors.h"
#include "caliper/utf8.h"
#include "caliper/vocabulary/weight_change.h"

namespace caliper::capture {

namespace {

constexpr double kOneDayS = 86400;
constexpr int kMaxAdjustments = 1000000;

// Messages are built with streams: GCC 12 warns (-Wrestrict, falsely) on long operator+ chains.
template <class... Parts>
std::string words(const Parts&... parts) {
  std::ostringstream s;
  (s << ... << parts);
  return s.str();
}

void check_instruction(const std::string& text) {
  if (text.empty())
    throw Error(ErrorKind::InvalidArgument,
                "instruction must not be empty: how_i_look, how_i_would_like_to_look, or free text of up to 200 characters",
                "instruction");
  std::size_t i = 0, count = 0;
  std::uint32_t cp = 0;
  while (i < text.size()) {
    if (!next_code_point(text, i, cp))
      throw Error(ErrorKind::InvalidArgument, words("instruction is not valid UTF-8 (byte ", i, ")"), "instruction");
    if (cp < 0x20 || (cp >= 0x7F && cp < 0xA0))
      throw Error(ErrorKind::InvalidArgument, "instruction must be one line of text without control characters", "instruction");
    ++count;
  }
  if (count > kMaxInstructionChars)
    throw Error(ErrorKind::OutOfRange,
                words("instruction has ", count, " characters; at most ", kMaxInstructionChars, " are accepted"), "instruction");
}

}  // namespace

const char* to_string(TaskKind kind) { return kind == TaskKind::Show ? "show" : "adjust"; }

const char* to_string(TaskState state) {
  switch (state) {
    case TaskState::Running: return "running";
    case TaskState::Answered: return "answered";
    case TaskState::Abandoned: return "abandoned";
  }
  return "running";
}

TaskKind parse_task_kind(const std::string& text) {
  if (text == "show") return TaskKind::Show;
  if (text == "adjust") return TaskKind::Adjust;
  throw Error(ErrorKind::InvalidArgument, "kind must be \"show\" or \"adjust\" (got \"" + text + "\")", "kind");
}

TaskState parse_task_state(const std::string& text) {
  if (text == "running") return TaskState::Running;
  if (text == "answered") return TaskState::Answered;
  if (text == "abandoned") return TaskState::Abandoned;
  throw Error(ErrorKind::Format, "unknown body-image task state '" + text + "'", "state");
}

void check_new_task(const NewBodyImageTask& t) {
  check_instruction(t.instruction);
  check_weight_change(t.range_min_pct, "range_pct");
  check_weight_change(t.range_max_pct, "range_pct");
  if (!(t.range_min_pct < t.range_max_pct))
    throw Error(ErrorKind::InvalidArgument,
                words("range_pct must be [min, max] with min < max (got [", t.range_min_pct, ", ", t.range_max_pct, "])"),
                "range_pct");
  check_weight_change(t.start_weight_change_pct, "start_weight_change_pct");
  if (t.start_weight_change_pct < t.range_min_pct || t.start_weight_change_pct > t.range_max_pct)
    throw Error(ErrorKind::OutOfRange,
                words("start_weight_change_pct = ", t.start_weight_change_pct, " % is outside range_pct [", t.range_min_pct, ", ",
                     t.range_max_pct, "]"),
                "start_weight_change_pct");
}

void check_answer(const BodyImageTask& task, const BodyImageAnswer& a) {
  const std::string range = words("[", task.range_min_pct, ", ", task.range_max_pct, "] %");
  if (!std::isfinite(a.chosen_weight_change_pct))
    throw Error(ErrorKind::InvalidArgument, "chosen_weight_change_pct must be a finite number in the task's range " + range,
                "chosen_weight_change_pct");
  if (a.chosen_weight_change_pct < task.range_min_pct || a.chosen_weight_change_pct > task.range_max_pct)
    throw Error(ErrorKind::OutOfRange,
                words("chosen_weight_change_pct = ", a.chosen_weight_change_pct, " % is outside the task's range ", range),
                "chosen_weight_change_pct");
  for (const auto& [value, field] : {std::pair{a.shown_at_s, "shown_at_s"}, std::pair{a.answered_at_s, "answered_at_s"}})
    if (!std::isfinite(value) || value < 0 || value > kOneDayS)
      throw Error(ErrorKind::OutOfRange, words(field, " must be a number of seconds in [0, 86400]"), field);
  if (a.answered_at_s < a.shown_at_s)
    throw Error(ErrorKind::InvalidArgument,
                words("answered_at_s (", a.answered_at_s, ") is before shown_at_s (", a.shown_at_s, ")"),
                "answered_at_s");
  if (a.adjustments < 0 || a.adjustments > kMaxAdjustments)
    throw Error(ErrorKind::OutOfRange, "adjustments must be a whole number in [0, 1000000]", "adjustments");
}

namespace {

using nlohmann::ordered_json;

// Decimal steps for the record: 0.01 % / kg / kg/m², 1 ms.
double rounded(double v, double inverse_step) { return std::round(v * inverse_step) / inverse_step; }

ordered_json optional_json(const std::optional<double>& v) { return v ? ordered_json(rounded(*v, 100)) : ordered_json(nullptr); }

ordered_json task_object(const BodyImageTask& t) {
  ordered_json j;
  j["id"] = t.id;
  j["kind"] = to_string(t.kind);
  j["instruction"] = t.instruction;
  j["start_weight_change_pct"] = rounded(t.start_weight_change_pct, 100);
  j["range_pct"] = {rounded(t.range_min_pct, 100), rounded(t.range_max_pct, 100)};
  j["state"] = to_string(t.state);
  j["created"] = t.created;
  if (!t.answer) {
    j["answer"] = nullptr;
    return j;
  }
  const BodyImageAnswer& a = *t.answer;
  j["answer"] = {{"chosen_weight_change_pct", rounded(a.chosen_weight_change_pct, 100)},
                 {"chosen_weight_kg", optional_json(a.chosen_weight_kg)},
                 {"chosen_bmi", optional_json(a.chosen_bmi)},
                 {"shown_at_s", rounded(a.shown_at_s, 1000)},
                 {"answered_at_s", rounded(a.answered_at_s, 1000)},
                 {"adjustments", a.adjustments},
                 {"answered", a.answered}};
  return j;
}

// A text cell: quoted when it holds a separator, a quote or a line break (RFC 4180). Text that a
// spreadsheet would run as a formula (starting with = + - @ or a tab) gets a leading apostrophe,
// so an experimenter's instruction cannot become a formula on the analyst's machine (OWASP's
// advice against CSV injection).
std::string csv_cell(const std::string& text) {
  const bool formula_like = !text.empty() && std::string("=+-@\t\r").find(text.front()) != std::string::npos;
  const std::string v = formula_like ? "'" + text : text;
  if (v.find_first_of(",\"\r\n") == std::string::npos) return v;
  std::string out = "\"";
  for (char c : v) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string csv_number(double v, double inverse_step) {
  std::ostringstream s;
  s.precision(12);  // every digit the rounding kept (seconds up to a day, to the millisecond)
  s << rounded(v, inverse_step);
  return s.str();
}
std::string csv_number(const std::optional<double>& v) { return v ? csv_number(*v, 100) : ""; }

}  // namespace

std::string body_image_task_json(const BodyImageTask& task) { return task_object(task).dump(); }

std::string write_session_json(const MeasurementSetFile& set, const std::vector<BodyImageTask>& tasks) {
  ordered_json j = ordered_json::parse(write_measurement_set_json(set));
  j["body_image_tasks"] = ordered_json::array();
  for (const auto& t : tasks) j["body_image_tasks"].push_back(task_object(t));
  return j.dump(2) + "\n";
}

std::string write_body_image_tasks_csv(const std::vector<BodyImageTask>& tasks) {
  std::ostringstream out;
  out << "task_id,kind,instruction,start_weight_change_pct,range_min_pct,range_max_pct,state,created,chosen_weight_change_pct,"
         "chosen_weight_kg,chosen_bmi,shown_at_s,answered_at_s,adjustments,answered\n";
  for (const auto& t : tasks) {
    std::vector<std::string> cells = {csv_cell(t.id), to_string(t.kind), csv_cell(t.instruction),
                                      csv_number(t.start_weight_change_pct, 100), csv_number(t.range_min_pct, 100),
                                      csv_number(t.range_max_pct, 100), to_string(t.state), csv_cell(t.created)};
    if (const auto& a = t.answer) {
      cells.insert(cells.end(), {csv_number(a->chosen_weight_change_pct, 100), csv_number(a->chosen_weight_kg),
                                 csv_number(a->chosen_bmi), csv_number(a->shown_at_s, 1000), csv_number(a->answered_at_s, 1000),
                                 std::to_string(a->adjustments), csv_cell(a->answered)});
    } else {
      cells.resize(cells.size() + 7);  // no answer: empty cells
    }
    for (size_t k = 0; k < cells.size(); ++k) out << (k ? "," : "") << cells[k];
    out << "\n";
  }
  return out.str();
}

}  // namespace caliper::capture
