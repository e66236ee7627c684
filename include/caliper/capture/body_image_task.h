// Body-image tasks run in the virtual mirror and stored with a capture session
// (docs/mirror-tasks.md): the experimenter shows the participant's avatar with its weight
// changed, or asks her to adjust it to "how I look" / "how I would like to look" (the paper's
// method-of-adjustment task, §4.3, Fig. 14). The answers are research data: they are validated
// here and written in one transaction each (store.h).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "caliper/capture/measurement_set.h"

namespace caliper::capture {

enum class TaskKind { Show, Adjust };
enum class TaskState { Running, Answered, Abandoned };
const char* to_string(TaskKind kind);    // "show" | "adjust"
const char* to_string(TaskState state);  // "running" | "answered" | "abandoned"
TaskKind parse_task_kind(const std::string& text);  // throws Error(InvalidArgument) naming "kind"
TaskState parse_task_state(const std::string& text);  // throws Error(Format) naming "state"

// The two instructions of the paper's task; any other is free text.
inline constexpr const char* kHowILook = "how_i_look";
inline constexpr const char* kHowIWouldLikeToLook = "how_i_would_like_to_look";
constexpr std::size_t kMaxInstructionChars = 200;  // Unicode code points

struct NewBodyImageTask {
  TaskKind kind = TaskKind::Adjust;
  std::string instruction = kHowILook;
  double start_weight_change_pct = 0;  // the body shown first
  double range_min_pct = -30, range_max_pct = 30;  // how far the participant may adjust
};

struct BodyImageAnswer {
  double chosen_weight_change_pct = 0;
  double shown_at_s = 0;     // headset clock, seconds: when the body was first shown
  double answered_at_s = 0;  // and when the participant confirmed (≥ shown_at_s)
  int adjustments = 0;       // thumbstick steps taken
  // Filled in by the service from the session's own values: the weight the chosen change means
  // for the person as measured (weight · (1 + p/100)) and its BMI (with the session's stature);
  // empty when the session has no weight (or stature).
  std::optional<double> chosen_weight_kg, chosen_bmi;
  std::string answered;  // server time, ISO 8601 UTC
};

struct BodyImageTask {
  std::string id;  // "t-…"
  TaskKind kind = TaskKind::Adjust;
  std::string instruction;
  double start_weight_change_pct = 0;
  double range_min_pct = -30, range_max_pct = 30;
  TaskState state = TaskState::Running;
  std::string created;  // ISO 8601 UTC
  std::optional<BodyImageAnswer> answer;
};

// Throws Error naming the field ("kind", "instruction", "start_weight_change_pct", "range_pct")
// and the accepted range: the weights in vocabulary/weight_change.h's range, min < max, the
// start within [min, max]; the instruction not empty, valid UTF-8 of at most
// kMaxInstructionChars code points, no control characters.
void check_new_task(const NewBodyImageTask& task);
// Throws Error naming the field ("chosen_weight_change_pct", "shown_at_s", "answered_at_s",
// "adjustments") unless the chosen change lies in the task's range, the times are finite,
// 0 ≤ shown_at_s ≤ answered_at_s ≤ one day of seconds, and 0 ≤ adjustments ≤ 1,000,000.
void check_answer(const BodyImageTask& task, const BodyImageAnswer& answer);

// One task as JSON text, the object the API and the exports carry: {"id", "kind",
// "instruction", "start_weight_change_pct", "range_pct": [min, max], "state", "created",
// "answer": null | {"chosen_weight_change_pct", "chosen_weight_kg", "chosen_bmi", "shown_at_s",
// "answered_at_s", "adjustments", "answered"}} (percent, kg, kg/m², seconds; unknown: null).
std::string body_image_task_json(const BodyImageTask& task);
// A capture session's JSON export: the measurement set (measurement_set.h) with the session's
// tasks, oldest first, under "body_image_tasks" (an array, empty when none ran);
// parse_measurement_set reads it back as the set.
std::string write_session_json(const MeasurementSetFile& set, const std::vector<BodyImageTask>& tasks);
// The tasks as a CSV table, a header line then one row per task, oldest first:
// task_id,kind,instruction,start_weight_change_pct,range_min_pct,range_max_pct,state,created,
// chosen_weight_change_pct,chosen_weight_kg,chosen_bmi,shown_at_s,answered_at_s,adjustments,
// answered (empty cells for a task without an answer; text cells quoted when they need it, and
// prefixed with ' when a spreadsheet would read them as a formula: = + - @ or a tab first).
std::string write_body_image_tasks_csv(const std::vector<BodyImageTask>& tasks);

}  // namespace caliper::capture
