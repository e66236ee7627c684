// Shared pieces of the `caliper` command-line client: exit codes, option groups, file output.
#pragma once
#include <CLI/CLI.hpp>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "caliper/caliper.h"

namespace caliper::cli {

// Exit codes (docs/cli.md): distinct per failure kind so scripts can react.
enum ExitCode : int {
  kOk = 0,
  kInternal = 1,
  kUsage = 2,          // bad options or arguments
  kBadValue = 3,       // NaN, negative, out-of-range or otherwise invalid value
  kBadFile = 4,        // unreadable, unwritable, malformed or truncated file
  // Not the caller's input at fault: a valid request the model cannot serve (e.g. a measurement
  // it lacks), or a file of the installation itself (a model found by name) is broken.
  kCannotServe = 5,
  kSuspectValues = 6,  // values that look swapped or in the wrong unit (--force uses them as given)
  kSomeRowsSkipped = 7,  // batch: the good rows were written, the bad ones listed on stderr and skipped
};
// Thrown by a command that did what it could and has already said why the rest failed: main
// returns the code and prints nothing more.
struct Finished {
  int code;
};
int exit_code_for(const Error& e);

// The measurement options shared by `avatar` and `render`.
struct BodyOptions {
  std::string sex = "female";
  std::string model = "mannequin";
  std::string regressor = "auto";
  std::map<std::string, double> values;     // canonical name → edge value (cm / kg)
  std::vector<std::string> extra;           // --set name=value
  std::string map_file;                     // real-to-virtual map
  std::string measurements_file;            // a measurement set (JSON/CSV); options given override it
  bool sex_given = false;                   // --sex was on the command line (else the file's sex is used)
  std::vector<double> beta;                 // explicit shape instead of measurements
  // auto / map: who measured (exact, self or other); empty: the measurement set's own
  // `measured_by`, else exact.
  std::string noise;
  std::vector<std::string> noise_sd;        // regressor "map": NAME=SD (cm or kg) overrides
  bool force = false;                       // build even if values look swapped or in the wrong unit
  // The same person with body weight changed by this many percent at the same stature
  // (avatar_weight_change.h); empty: the avatar as measured.
  std::optional<double> weight_change_pct;
};
void add_body_options(CLI::App& app, BodyOptions& opts, bool allow_beta);

// Loads the model and builds the avatar the options describe (β given, or regressed).
struct BuiltAvatar {
  std::shared_ptr<const BodyModel> model;
  Avatar avatar;
};
// Builds the avatar the options describe; its warnings and an implausible verdict are printed on
// standard error.
BuiltAvatar build_avatar(const BodyOptions& opts);

void write_file(const std::string& path, const std::string& bytes);

// After CLI11 refused the command line: on stderr, "did you mean --height" for a misspelt option
// and a hint for a value typed with its unit (165cm) or a decimal comma (165,5).
void explain_parse_error(const CLI::App& app, int argc, char** argv);
// "165cm", "62 kg" → a hint that units are implied; "165,5" → use a dot; "" for anything else.
std::string value_hint(const std::string& text);
// "--set: unknown measurement 'chest'; did you mean chest_height, …? The accepted names: …".
std::string unknown_measurement_message(const std::string& name, const std::string& option);
// The names closest to `word` (sharing a part of it, or a typing slip away), best first.
std::vector<std::string> closest_names(const std::string& word, const std::vector<std::string>& names);

// A progress bar on stderr for long work: redrawn in place on a terminal, a line per 10 % otherwise.
std::function<void(int, int)> progress_bar(const std::string& label);

void register_avatar(CLI::App& app);
void register_measure(CLI::App& app);
void register_model(CLI::App& app);
void register_isak(CLI::App& app);
void register_map(CLI::App& app);
void register_eval(CLI::App& app);
void register_batch(CLI::App& app);
void register_render(CLI::App& app);
void register_serve(CLI::App& app);  // cmd_serve.cpp: the desktop tool
void register_sessions(CLI::App& app);  // cmd_sessions.cpp: capture sessions

}  // namespace caliper::cli
