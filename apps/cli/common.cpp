#include "common.h"

#include "caliper/capture/measurement_set.h"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <iostream>
#include <unistd.h>

namespace caliper::cli {

int exit_code_for(const Error& e) {
  if (dynamic_cast<const SuspectInputError*>(&e)) return kSuspectValues;
  if (e.from_installation()) return kCannotServe;
  switch (e.kind()) {
    case ErrorKind::InvalidArgument:
    case ErrorKind::OutOfRange: return kBadValue;
    case ErrorKind::Io:
    case ErrorKind::Format: return kBadFile;
    case ErrorKind::Unsupported: return kCannotServe;
  }
  return kInternal;
}

namespace {
// A measurement option: "--stature CM" plus aliases; the value is checked later so the error can
// name the field and the accepted range.
void add_measurement(CLI::App& app, BodyOptions& opts, const std::string& name, const std::string& flags) {
  const MeasurementInfo* info = find_measurement_info(name);
  const std::string help = info->label + " (" + edge_unit(*info) + ", " + std::to_string(int(info->min_edge)) + "–" +
                           std::to_string(int(info->max_edge)) + ")";
  app.add_option_function<double>(flags, [&opts, name](const double& v) { opts.values[name] = v; }, help)
      ->type_name(edge_unit(*info) == std::string("kg") ? "KG" : "CM");
}
}  // namespace

void add_body_options(CLI::App& app, BodyOptions& opts, bool allow_beta) {
  app.add_option("--sex", opts.sex, "female, male or neutral")->capture_default_str()->each([&opts](const std::string&) {
    opts.sex_given = true;
  });
  app.add_option("--measurements", opts.measurements_file,
                 "a measurement set file (JSON or CSV, as `caliper sessions export` and the desktop tool write); "
                 "values given as options override it");
  app.add_option("--model", opts.model, "body model: a name in the models folder (see `caliper model list`) or a .npz path")
      ->capture_default_str();
  app.add_option("--regressor", opts.regressor,
                 "auto (the default: the noise-aware estimator over every value given, with uncertainty; map is the "
                 "same), the paper's presets R2, R4, R5, R6, or a comma list of measurements")
      ->capture_default_str();
  app.add_option("--noise", opts.noise,
                 "who measured, for auto: exact (values reproduced as given), self or other (weighed by the paper's "
                 "Table 2 errors); default: the measurement set's measured_by, else exact")
      ->check(CLI::IsMember({"exact", "self", "other"}));
  app.add_flag("--force", opts.force,
               "build even when values look swapped or in the wrong unit (e.g. --height 60 --weight 165); without it "
               "they are refused with what was probably meant (exit code 6)");
  app.add_option("--noise-sd", opts.noise_sd, "for auto: a measurement's noise SD as NAME=SD (cm or kg)")
      ->type_name("NAME=SD");
  add_measurement(app, opts, "stature", "--stature,--height");
  add_measurement(app, opts, "weight", "--weight");
  add_measurement(app, opts, "span", "--span,--arm-span");
  add_measurement(app, opts, "crotch_height", "--crotch-height,--inseam");
  add_measurement(app, opts, "hip_breadth", "--hip-breadth,--hip-width");
  add_measurement(app, opts, "arm_length", "--arm-length");
  app.add_option("--set", opts.extra, "any other measurement as NAME=VALUE (cm or kg), e.g. chest_circumference=95")
      ->type_name("NAME=VALUE");
  app.add_option_function<double>(
         "--weight-change", [&opts](const double& v) { opts.weight_change_pct = v; },
         "the same person with body weight changed by this many percent at the same stature (-50 to 100): the "
         "estimator keeps the lengths given and lets the girths follow (docs/cli.md)")
      ->type_name("PERCENT");
  app.add_option("--map", opts.map_file, "real-to-virtual map (JSON, see `caliper map fit`) applied to the inputs instead of the model's own");
  if (allow_beta)
    app.add_option("--beta", opts.beta, "shape values instead of measurements (comma separated)")->delimiter(',');
}

namespace {
// "NAME=VALUE" → (name, number); throws Error naming the option or the field.
std::pair<std::string, double> name_value(const std::string& kv, const std::string& option) {
  const auto eq = kv.find('=');
  if (eq == std::string::npos) throw Error(ErrorKind::InvalidArgument, option + " expects NAME=VALUE, got '" + kv + "'", option);
  const std::string name = kv.substr(0, eq), text = kv.substr(eq + 1);
  double v = 0;
  try {
    size_t used = 0;
    v = std::stod(text, &used);
    if (used != text.size()) throw std::invalid_argument("trailing");
  } catch (const std::exception&) {
    const std::string hint = value_hint(text);
    throw Error(ErrorKind::InvalidArgument, name + " must be a number, got " + (hint.empty() ? "'" + text + "'" : hint), name);
  }
  return {name, v};
}
}  // namespace

namespace {
// Warnings and an implausible shape go to standard error whatever else is printed (-q included):
// a body the user should not trust must not pass unnoticed in a script.
void warn(const Avatar& a) {
  for (const auto& w : a.warnings) std::cerr << "caliper: warning: " << w << "\n";
  if (a.plausibility.overall == Verdict::Implausible)
    std::cerr << "caliper: warning: the shape is implausible, " << a.plausibility.rarity << ": "
              << a.plausibility.explanation << "\n";
}
}  // namespace

static BuiltAvatar build_avatar_quietly(const BodyOptions& opts);

BuiltAvatar build_avatar(const BodyOptions& opts) {
  BuiltAvatar out = build_avatar_quietly(opts);
  warn(out.avatar);
  return out;
}

static BuiltAvatar build_avatar_quietly(const BodyOptions& opts) {
  Sex sex = parse_sex(opts.sex);
  BuiltAvatar out;
  std::map<std::string, double> edge = opts.values;
  std::string noise = opts.noise;
  if (!opts.measurements_file.empty()) {
    const MeasurementSetFile file = read_measurement_set(opts.measurements_file);
    for (const auto& [name, value] : file.edge) edge.emplace(name, value);  // options win
    if (file.sex && !opts.sex_given) sex = *file.sex;
    // A capture session's values carry who measured them, so the avatar is the headset mirror's.
    if (file.measured_by && noise.empty()) noise = *file.measured_by;
  }
  if (noise.empty()) noise = "exact";
  std::set<std::string> set_names;  // canonical names given with --set
  for (const auto& kv : opts.extra) {
    const auto [name, v] = name_value(kv, "--set");
    // Two values for one measurement on the command line is a mistake to report, not to settle
    // silently (the measurement file's values are meant to be overridden by options).
    if (const MeasurementInfo* info = find_measurement_info(name)) {
      if (opts.values.count(info->name) || !set_names.insert(info->name).second)
        throw Error(ErrorKind::InvalidArgument, info->name + " is given twice on the command line", info->name);
      edge[info->name] = v;
    } else {
      throw Error(ErrorKind::InvalidArgument, unknown_measurement_message(name, "--set"), name);
    }
  }
  EdgeAvatarRequest edge_request;
  for (const auto& kv : opts.noise_sd) {
    const auto [name, v] = name_value(kv, "--noise-sd");
    if (!find_measurement_info(name))
      throw Error(ErrorKind::InvalidArgument, unknown_measurement_message(name, "--noise-sd"), "--noise-sd");
    edge_request.noise_sd[name] = v;
  }
  // With nothing given, say which options the command needs.
  if (edge.empty() && opts.beta.empty())
    throw Error(ErrorKind::InvalidArgument,
                "no measurements given: give at least stature and weight (e.g. --height 165 --weight 62), a "
                "measurement set (--measurements FILE) or shape values (--beta 0 for the mean body)",
                "measurements");
  if (opts.weight_change_pct) check_weight_change(*opts.weight_change_pct, "--weight-change");
  if (!opts.beta.empty()) {
    if (!edge.empty())
      throw Error(ErrorKind::InvalidArgument, "give either --beta or measurements, not both", "--beta");
    if (opts.weight_change_pct)
      throw Error(ErrorKind::InvalidArgument, "--weight-change needs measurements (it keeps the lengths given), not --beta",
                  "--weight-change");
    out.model = std::make_shared<const BodyModel>(load_model(opts.model, sex));
    // β ~ N(0, I): beyond ±5 SD the shape space extrapolates into bodies that are not bodies.
    for (size_t k = 0; k < opts.beta.size(); ++k)
      if (!std::isfinite(opts.beta[k]) || std::abs(opts.beta[k]) > 5) {
        std::ostringstream msg;
        msg << "beta[" << k + 1 << "] = " << opts.beta[k] << " is outside the accepted range [-5, 5] (SD from the mean body)";
        throw Error(ErrorKind::OutOfRange, msg.str(), "--beta");
      }
    Eigen::VectorXd beta = Eigen::Map<const Eigen::VectorXd>(opts.beta.data(), static_cast<Eigen::Index>(opts.beta.size()));
    Avatar& a = out.avatar;
    a.regressor = "none (beta given)";
    a.beta = beta;
    a.rest_vertices = out.model->rest_vertices(beta);
    a.joints = out.model->joints(a.rest_vertices);
    a.plausibility = judge_plausibility(beta);
    a.achieved = measure_all(*out.model, a.rest_vertices);
    return out;
  }
  edge_request.measurements = edge;
  edge_request.estimator = opts.regressor;
  edge_request.noise = noise;
  edge_request.force = opts.force;
  // A user's own map replaces the model's default one.
  if (!opts.map_file.empty()) edge_request.maps = RealToVirtual::load(opts.map_file);
  // Values are checked before the model is loaded, so a bad value is reported as such.
  const AvatarRequest request = avatar_request_from_edge(edge_request);
  out.model = std::make_shared<const BodyModel>(load_model(opts.model, sex));
  AvatarBuilder builder(out.model);
  out.avatar = builder.build(request);
  if (opts.weight_change_pct) out.avatar = with_weight_change(builder, out.avatar, *opts.weight_change_pct);
  return out;
}

void write_file(const std::string& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  if (!f) throw Error(ErrorKind::Io, "cannot write '" + path + "'", path);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!f) throw Error(ErrorKind::Io, "failed writing '" + path + "'", path);
}

std::function<void(int, int)> progress_bar(const std::string& label) {
  const bool tty = isatty(STDERR_FILENO) != 0;
  auto last = std::make_shared<int>(-1);
  return [=](int done, int total) {
    const int width = 40, filled = total ? done * width / total : width;
    if (tty) {
      if (filled == *last && done != total) return;
      *last = filled;
      std::cerr << "\r" << label << " [" << std::string(filled, '#') << std::string(width - filled, ' ') << "] " << done
                << "/" << total << std::flush;
      if (done == total) std::cerr << "\n";
    } else {
      const int tenth = total ? done * 10 / total : 10;
      if (tenth == *last) return;
      *last = tenth;
      std::cerr << label << ": " << done << "/" << total << "\n";
    }
  };
}

}  // namespace caliper::cli
