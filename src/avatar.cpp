// The pipeline behind `caliper avatar`: measurements → regressor → β → body → measurements.
#include "caliper/avatar.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "caliper/errors.h"
#include "caliper/vocabulary/catalogue.h"
#include "caliper/measure/input_check.h"
#include "caliper/measure/measure.h"

namespace caliper {

AvatarBuilder::AvatarBuilder(std::shared_ptr<const BodyModel> model)
    : model_(model ? std::move(model) : throw Error(ErrorKind::InvalidArgument, "no body model", "model")), map_(model_) {
  auto it = model_->data().metadata.find("real_to_virtual");
  if (it == model_->data().metadata.end()) return;
  const auto read_maps = [&] { return RealToVirtual::from_json(it->second); };
  maps_ = model_->data().supplied_by == ErrorOrigin::Installation ? installation_input(read_maps) : read_maps();
}

namespace {

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    if (item.empty()) continue;
    const MeasurementInfo* info = find_measurement_info(item);
    if (!info) throw Error(ErrorKind::InvalidArgument, "unknown measurement '" + item + "' in the regressor's inputs", "regressor");
    out.push_back(info->name);
  }
  return out;
}

// Whom "plausible" refers to: the model's own words (metadata `population`, written when the
// model is built), else its data source.
std::string population_description(const BodyModel& model) {
  const auto& meta = model.data().metadata;
  if (auto it = meta.find("population"); it != meta.end()) return it->second;
  if (auto it = meta.find("source"); it != meta.end()) return it->second;
  return "the population model '" + model.name() + "' was built from";
}

}  // namespace

std::size_t AvatarBuilder::custom_regressor_count() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return custom_.size();
}

std::shared_ptr<const Regressor> AvatarBuilder::regressor(const std::string& name, const std::vector<std::string>& inputs) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const bool preset = std::find(preset_names().begin(), preset_names().end(), name) != preset_names().end();
  if (preset) {
    if (auto it = presets_.find(name); it != presets_.end()) return it->second;
  } else {
    if (const auto* cached = custom_.find(name)) return *cached;
  }
  for (const auto& m : inputs)
    if (!model_->find_measurement(m))
      throw Error(ErrorKind::Unsupported, "model '" + model_->name() + "' cannot measure '" + m + "'", m);
  // The corner design grows by the columns a new regressor needs; bodies are rebuilt only for them.
  // The first design takes every preset input the model can measure at once, so training the four
  // presets measures the 2^K corner bodies a single time.
  std::vector<std::string> wanted = inputs;
  if (!design_)
    for (const auto& m : preset_inputs("R6"))
      if (model_->find_measurement(m) && std::find(wanted.begin(), wanted.end(), m) == wanted.end()) wanted.push_back(m);
  std::vector<std::string> missing;
  for (const auto& m : wanted)
    if (!design_ || std::find(design_->feature_names.begin(), design_->feature_names.end(), m) == design_->feature_names.end())
      missing.push_back(m);
  if (!missing.empty()) {
    CornerDesign extra = build_corner_design(*model_, missing);
    if (!design_) {
      design_ = std::make_unique<CornerDesign>(std::move(extra));
    } else {
      const Eigen::Index old = design_->features.cols();
      design_->features.conservativeResize(Eigen::NoChange, old + extra.features.cols());
      design_->features.rightCols(extra.features.cols()) = extra.features;
      design_->feature_names.insert(design_->feature_names.end(), missing.begin(), missing.end());
    }
  }
  // The design's columns are bounded by the catalogue (one per measurement), so it is kept whole.
  auto r = std::make_shared<const Regressor>(*design_, inputs, name);
  if (preset) {
    presets_[name] = r;
  } else {
    custom_.insert(name, r);  // the least recently used beyond kMaxCustomRegressors is dropped
  }
  return r;
}

Avatar AvatarBuilder::build_map(const AvatarRequest& request) const {
  // The noise-aware estimator: every given measurement the model can measure is an input.
  MapOptions options;
  options.noise = parse_noise_setting(request.noise);
  options.measurement_uncertainty = request.measure_avatar;
  options.uncertainty_of = request.measure_only;
  options.vertex_uncertainty = request.vertex_uncertainty;
  // The best body the model can make stays inside its population: not implausible (rarer than
  // 1 in 1,000 of its people, regress/regressor.h).
  options.within_population = [](const Eigen::VectorXd& beta) {
    return judge_plausibility(beta).overall != Verdict::Implausible;
  };
  Avatar avatar;
  avatar.regressor = "map";
  avatar.noise = to_string(options.noise);
  avatar.requested = request.measurements;
  apply_maps(request, avatar);
  std::map<std::string, double> inputs;
  for (const auto& [name, value] : avatar.targets) {
    if (!model_->find_measurement(name)) {
      avatar.warnings.push_back(name + " is not used: model '" + model_->name() + "' cannot measure it");
      continue;
    }
    inputs[name] = value;
    avatar.inputs.push_back(name);
    double sd = default_noise_sd(*model_, name, options.noise);
    if (auto o = request.noise_sd.find(name); o != request.noise_sd.end()) sd = o->second;
    // A real → virtual map scales the noise with the value (σ_virtual = |slope|·σ_real) and adds
    // its own residual: the T-posed avatar's arm length is not a function of the hanging arm's
    // alone (paper §3.3), so it is not pinned tighter than the map knows it (else it drags
    // biacromial breadth, docs/evaluation.md).
    if (const LinearMap& m = avatar.real_to_virtual.map(name); !m.is_identity())
      sd = std::hypot(std::abs(m.slope) * sd, m.rmse);
    options.noise_sd[name] = sd;
  }
  for (const auto& [name, sd] : request.noise_sd)
    if (!request.measurements.count(name))
      throw Error(ErrorKind::InvalidArgument, "a noise SD was given for " + name + ", which is not among the measurements", name);
  if (inputs.empty())
    throw Error(ErrorKind::Unsupported, "map needs at least one measurement the model can measure", "measurements");
  // The words say each value as the person measured it (the estimator works in the model's terms).
  const RealToVirtual maps = avatar.real_to_virtual;
  options.as_measured = [maps](const std::string& name, double value) { return maps.map(name).invert(value); };
  const MapEstimate est = map_.estimate(inputs, options);
  avatar.beta = est.beta;
  avatar.beta_covariance = est.covariance;
  avatar.uncertainty = est.measurement_sd;
  avatar.vertex_sd = est.vertex_sd;
  avatar.input_fits = est.inputs;
  avatar.noise_widened = est.noise_widened;
  avatar.warnings.insert(avatar.warnings.begin(), est.warnings.begin(), est.warnings.end());
  finish(request, avatar);
  avatar.plausibility.drivers = describe_drivers(*model_, est.inputs, options.as_measured);
  // Measurements not asked for (measure_only) keep no SD, so the report lists matching keys.
  if (!request.measure_only.empty())
    for (auto it = avatar.uncertainty.begin(); it != avatar.uncertainty.end();)
      it = avatar.achieved.count(it->first) ? std::next(it) : avatar.uncertainty.erase(it);
  return avatar;
}

void AvatarBuilder::apply_maps(const AvatarRequest& request, Avatar& avatar) const {
  if (request.apply_model_maps) avatar.real_to_virtual = request.maps ? *request.maps : maps_;
  avatar.targets = request.measurements;
  avatar.real_to_virtual.apply(avatar.targets);
}

void AvatarBuilder::finish(const AvatarRequest& request, Avatar& avatar) const {
  avatar.rest_vertices = model_->rest_vertices(avatar.beta);
  avatar.joints = model_->joints(avatar.rest_vertices);
  avatar.plausibility = judge_plausibility(avatar.beta);
  avatar.plausibility.population = population_description(*model_);
  avatar.requested = request.measurements;
  if (!request.measure_avatar) {
    // Nothing measured: the caller only wants the body.
  } else if (request.measure_only.empty()) {
    avatar.achieved = measure_all(*model_, avatar.rest_vertices);
  } else {
    avatar.achieved = measure_some(*model_, request.measure_only, avatar.rest_vertices);
  }
}

Avatar AvatarBuilder::build(const AvatarRequest& request) const {
  Avatar avatar;
  std::string key = request.regressor;
  std::vector<std::string> inputs;
  std::string upper = key;
  for (auto& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  // "auto", the default, is the noise-aware estimator over whatever was given; the
  // paper's presets stay selectable by name.
  if (upper == "MAP" || upper == "AUTO") return build_map(request);
  if (upper.size() == 2 && upper[0] == 'R') {
    key = upper;
    inputs = preset_inputs(key);
  } else {
    // Any other subset: "custom:stature,weight,chest_circumference" or the bare list.
    const std::string list = key.rfind("custom:", 0) == 0 ? key.substr(7) : key;
    inputs = split_list(list);
    if (inputs.empty())
      throw Error(ErrorKind::InvalidArgument,
                  "unknown regressor '" + request.regressor + "' (R2, R4, R5, R6, auto, map, or a comma list of measurements)",
                  "regressor");
    std::sort(inputs.begin(), inputs.end());
    inputs.erase(std::unique(inputs.begin(), inputs.end()), inputs.end());
    key = "custom:";
    for (size_t i = 0; i < inputs.size(); ++i) key += (i ? "," : "") + inputs[i];
  }
  for (const auto& m : inputs)
    if (!request.measurements.count(m))
      throw Error(ErrorKind::Unsupported, "regressor " + key + " needs " + m + ", which was not given", m);
  const std::shared_ptr<const Regressor> r = regressor(key, inputs);
  avatar.regressor = key;
  avatar.inputs = inputs;
  apply_maps(request, avatar);
  avatar.beta = r->predict(*model_, avatar.targets);
  finish(request, avatar);
  warn_about_inputs(avatar);
  return avatar;
}

// A regressor uses only its own inputs and reproduces them exactly within the population; say
// so when a given value was left out, or when the body could not reach an input (a combination
// far outside the population, e.g. 60 cm and 290 kg), instead of returning a silently wrong body.
void AvatarBuilder::warn_about_inputs(Avatar& avatar) const {
  for (const auto& [name, value] : avatar.requested)
    if (std::find(avatar.inputs.begin(), avatar.inputs.end(), name) == avatar.inputs.end())
      avatar.warnings.push_back(name + " was given but " + avatar.regressor +
                                " does not use it; --regressor map (or a regressor listing it) uses every value");
  for (const auto& name : avatar.inputs) {
    const auto target = avatar.targets.find(name);
    const auto got = avatar.achieved.find(name);
    if (target == avatar.targets.end() || got == avatar.achieved.end()) continue;
    const MeasurementInfo* info = find_measurement_info(name);
    if (!info) continue;
    const bool kg = info->unit == Unit::Kilogram;
    const double tolerance = std::max(kg ? 2.0 : 0.01, 0.03 * std::abs(target->second));  // 2 kg or 1 cm, 3 %
    if (std::abs(got->second - target->second) <= tolerance) continue;
    std::ostringstream msg;
    // Said in the person's terms, as the table and the report show it.
    const double reached = as_measured(avatar, name, got->second), asked = avatar.requested.at(name);
    msg << std::fixed << std::setprecision(1) << name << ": the body reaches " << si_to_edge(*info, reached) << " "
        << edge_unit(*info) << ", not the " << si_to_edge(*info, asked) << " " << edge_unit(*info)
        << " asked: these values together lie outside what the model can represent";
    avatar.warnings.push_back(msg.str());
  }
}

double as_measured(const Avatar& avatar, const std::string& name, double rest_pose_value) {
  return avatar.real_to_virtual.map(name).invert(rest_pose_value);
}

double sd_as_measured(const Avatar& avatar, const std::string& name, double rest_pose_sd) {
  return rest_pose_sd / std::abs(avatar.real_to_virtual.map(name).slope);
}

bool measured_differs_from_rest_pose(const Avatar& avatar, const std::string& name) {
  return !avatar.real_to_virtual.map(name).is_identity();
}

std::map<std::string, double> measurements_from_edge(const std::map<std::string, double>& edge_values) {
  std::map<std::string, double> si;
  for (const auto& [name, value] : edge_values) {
    const MeasurementInfo* info = find_measurement_info(name);
    if (!info) throw Error(ErrorKind::InvalidArgument, "unknown measurement '" + name + "'", name);
    if (si.count(info->name))
      throw Error(ErrorKind::InvalidArgument, info->name + " was given twice (as '" + name + "' and another alias)", info->name);
    si[info->name] = edge_to_si(*info, value);
  }
  return si;
}

namespace {
// Values as typed by name or alias → by canonical name (unknown names kept for
// measurements_from_edge to name); a measurement given twice under two names is refused.
std::map<std::string, double> by_canonical_name(const std::map<std::string, double>& edge_values) {
  std::map<std::string, double> canonical;
  for (const auto& [name, value] : edge_values) {
    const MeasurementInfo* info = find_measurement_info(name);
    const std::string key = info ? info->name : name;
    if (!canonical.emplace(key, value).second)
      throw Error(ErrorKind::InvalidArgument, key + " is given twice (as '" + name + "' and another alias)", key);
  }
  return canonical;
}

// Noise SDs as typed (cm or kg, by name or alias) → SI by canonical name.
std::map<std::string, double> noise_sd_from_edge(const std::map<std::string, double>& edge_sd) {
  std::map<std::string, double> si;
  for (const auto& [name, sd] : edge_sd) {
    const MeasurementInfo* info = find_measurement_info(name);
    // The field is the SD's, not the measurement's: a client must not be told its stature is wrong.
    if (!info) throw Error(ErrorKind::InvalidArgument, "noise SD of an unknown measurement '" + name + "'", "noise_sd." + name);
    if (!std::isfinite(sd) || sd <= 0 || sd > 50)
      throw Error(ErrorKind::OutOfRange, "the noise SD of " + info->name + " must be in (0, 50] " + edge_unit(*info),
                  "noise_sd." + info->name);
    si[info->name] = info->unit == Unit::Kilogram ? sd : sd / 100.0;
  }
  return si;
}
}  // namespace

AvatarRequest avatar_request_from_edge(const EdgeAvatarRequest& edge) {
  // With nothing given the estimator would fail deep inside with an "unsupported" error.
  if (edge.measurements.empty())
    throw Error(ErrorKind::InvalidArgument, "no measurements given: give at least stature (cm) and weight (kg)",
                "measurements");
  const std::map<std::string, double> values = by_canonical_name(edge.measurements);
  // Typing mistakes are asked about before the range checks, which would only say "out of range".
  if (!edge.force)
    if (auto suspects = suspect_input_mistakes(values); !suspects.empty()) throw SuspectInputError(std::move(suspects));
  AvatarRequest request;
  request.measurements = measurements_from_edge(values);
  request.regressor = edge.estimator;
  request.noise = edge.noise;
  request.noise_sd = noise_sd_from_edge(edge.noise_sd);
  request.maps = edge.maps;
  return request;
}

}  // namespace caliper
