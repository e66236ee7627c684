// The same person heavier or lighter at the same stature (include/caliper/avatar_weight_change.h).
// The body-image studies the paper serves (§1, §4.3: the method-of-adjustment task of Fig. 14)
// show a participant her own avatar with its weight changed; a scaled body would change her
// height and bone lengths too. Here the estimator (regress/map_estimator.h) builds the change.
#include "caliper/avatar_weight_change.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "caliper/errors.h"
#include "caliper/measure/measure.h"
#include "caliper/vocabulary/catalogue.h"

namespace caliper {

namespace {

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// The names the changed bodies keep: stature always, and every skeletal measurement the person
// gave that the model can measure.
std::vector<std::string> kept_measurements(const BodyModel& model, const Avatar& original) {
  std::vector<std::string> kept = {"stature"};
  for (const auto& [name, value] : original.requested)
    if (name != "stature" && !follows_body_weight(name) && model.find_measurement(name)) kept.push_back(name);
  return kept;
}

// The estimator's β for the kept values (model terms, the original body's own) at `weight_kg`.
Eigen::VectorXd estimate_at_weight(const AvatarBuilder& builder, std::map<std::string, double> kept, double weight_kg) {
  AvatarRequest request;
  kept["weight"] = weight_kg;
  request.measurements = std::move(kept);
  request.regressor = "map";
  request.noise = "exact";
  // The lengths are kept (0.1 mm); the weight, 0.5 kg, gives way first when the population holds
  // no body with all of them (the estimator then widens every SD by one factor).
  request.noise_sd["weight"] = 0.5;
  request.apply_model_maps = false;  // the values are the rest-pose body's already
  request.vertex_uncertainty = false;
  request.measure_avatar = false;
  return builder.build(request).beta;
}

Avatar changed_body(const AvatarBuilder& builder, const Avatar& original, const std::map<std::string, double>& kept,
                    double weight_kg, const Eigen::VectorXd& delta, double pct) {
  const BodyModel& model = builder.model();
  Avatar a;
  a.regressor = original.regressor;
  a.beta = original.beta + delta;
  a.rest_vertices = model.rest_vertices(a.beta);
  a.joints = model.joints(a.rest_vertices);
  a.plausibility = judge_plausibility(a.beta);
  a.plausibility.population = original.plausibility.population;
  a.real_to_virtual = original.real_to_virtual;
  for (const auto& [name, value] : kept) {
    a.inputs.push_back(name);
    a.targets[name] = value;
    a.requested[name] = original.real_to_virtual.map(name).invert(value);  // as the person measures it
  }
  a.inputs.push_back("weight");
  a.targets["weight"] = a.requested["weight"] = weight_kg;
  if (!original.achieved.empty()) a.achieved = measure_all(model, a.rest_vertices);
  const double reached = original.achieved.empty() ? measure_some(model, {"weight"}, a.rest_vertices).at("weight")
                                                   : a.achieved.at("weight");
  // The estimator keeps bodies inside the model's population: a change beyond it is not reached.
  if (std::abs(reached - weight_kg) > std::max(1.0, 0.02 * weight_kg)) {
    std::ostringstream msg;
    msg << std::fixed << std::setprecision(1) << "weight changed by " << pct << " %: the body reaches " << reached
        << " kg, not the " << weight_kg << " kg asked; the model's population holds no plausible body that far";
    a.warnings.push_back(msg.str());
  }
  return a;
}

}  // namespace

bool follows_body_weight(const std::string& measurement) {
  if (measurement == "weight") return true;
  if (ends_with(measurement, "_circumference") || ends_with(measurement, "_depth")) return true;
  static const std::vector<std::string> bony = {"biacromial_breadth", "head_breadth", "hand_breadth", "foot_breadth"};
  return ends_with(measurement, "_breadth") && std::find(bony.begin(), bony.end(), measurement) == bony.end();
}

std::vector<Avatar> with_weight_changes(const AvatarBuilder& builder, const Avatar& original, const std::vector<double>& pcts) {
  for (double p : pcts) check_weight_change(p);
  const BodyModel& model = builder.model();
  if (original.beta.size() != model.shape_count())
    throw Error(ErrorKind::InvalidArgument, "the original avatar was not built with this model", "original");
  std::vector<std::string> names = kept_measurements(model, original);
  names.push_back("weight");
  std::map<std::string, double> kept = measure_some(model, names, original.rest_vertices);
  const double weight_kg = kept.at("weight");
  kept.erase("weight");
  Eigen::VectorXd at_original;  // β(0), solved once when some change is not 0
  std::vector<Avatar> out;
  out.reserve(pcts.size());
  for (double p : pcts) {
    if (p == 0) {
      out.push_back(original);
      continue;
    }
    if (at_original.size() == 0) at_original = estimate_at_weight(builder, kept, weight_kg);
    const double target = weight_kg * (1 + p / 100);
    const Eigen::VectorXd delta = estimate_at_weight(builder, kept, target) - at_original;
    out.push_back(changed_body(builder, original, kept, target, delta, p));
  }
  return out;
}

Avatar with_weight_change(const AvatarBuilder& builder, const Avatar& original, double pct) {
  return with_weight_changes(builder, original, {pct}).front();
}

}  // namespace caliper
