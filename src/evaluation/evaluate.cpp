// Evaluation against real people (ANSUR II) and a synthetic surface study (paper §4.2).
#include "caliper/evaluation/evaluate.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>
#include <tuple>

#include "caliper/errors.h"
#include "caliper/evaluation/linear_limit.h"
#include "caliper/vocabulary/catalogue.h"
#include "caliper/vocabulary/noise.h"
#include "caliper/measure/measure.h"
#include "caliper/random.h"
#include "parallel.h"

namespace caliper {

MeasurementNoise parse_noise(const std::string& text) {
  if (text == "none") return MeasurementNoise::None;
  if (text == "self") return MeasurementNoise::Self;
  if (text == "other") return MeasurementNoise::Other;
  throw Error(ErrorKind::InvalidArgument, "noise must be none, self or other (got '" + text + "')", "noise");
}

const char* to_string(MeasurementNoise noise) {
  switch (noise) {
    case MeasurementNoise::None: return "none";
    case MeasurementNoise::Self: return "self";
    case MeasurementNoise::Other: return "other";
  }
  return "none";
}

std::map<std::string, double> table2_mae(MeasurementNoise noise) {
  if (noise == MeasurementNoise::None) return {};
  return paper_table2_mae(noise == MeasurementNoise::Self ? MeasuredBy::Self : MeasuredBy::Other);
}

std::string map_noise_for(MeasurementNoise noise) {
  switch (noise) {
    case MeasurementNoise::None: return "exact";
    case MeasurementNoise::Self: return "self";
    case MeasurementNoise::Other: return "other";
  }
  return "exact";
}

namespace {

// The Virtual Caliper inputs under the names the evaluation reports (ANSUR's, lowercase).
const std::vector<std::pair<std::string, std::string>>& input_keys() {
  static const std::vector<std::pair<std::string, std::string>> keys = {
      {"stature", "stature"}, {"weight", "weight"}, {"span", "span"}, {"crotch_height", "crotchheight"},
      {"hip_breadth", "hipbreadth"}, {"arm_length", "armlength"}};
  return keys;
}

// One subject's signed errors per method and key (NaN = not applicable), and plausibility.
struct SubjectErrors {
  std::map<std::string, std::map<std::string, double>> inputs, inputs_vs_truth, held_out;
  std::map<std::string, bool> implausible, failed;
  std::map<std::string, std::map<std::string, double>> linear;  // the linear limit's errors, per method
  // "map": per key, |avatar − truth| / predicted SD and the SD itself.
  std::map<std::string, std::map<std::string, std::pair<double, double>>> standardised;
};

ErrorStats stats_of(const std::vector<double>& errors) {
  ErrorStats s;
  for (double e : errors) {
    if (std::isnan(e)) continue;
    s.mae += std::abs(e);
    s.bias += e;
    s.max = std::max(s.max, std::abs(e));
    ++s.count;
  }
  if (s.count) { s.mae /= s.count; s.bias /= s.count; }
  return s;
}

std::vector<std::string> measured_names() {
  std::vector<std::string> names;
  for (const auto& [canonical, key] : input_keys()) names.push_back(canonical);
  for (const auto& [col, m] : held_out_columns()) names.push_back(m);
  return names;
}

// The linear limits that predict one subject, by method (null: none for that method).
using LimitsFor = std::function<const LinearLimit*(const std::string& method)>;

void evaluate_one(const AnsurSubject& s, const AvatarBuilder& builder, const Vertices& mean_body,
                  const EvaluationOptions& opt, std::uint64_t subject_seed, const LimitsFor& limits, SubjectErrors& out) {
  const std::map<std::string, double> truth = virtual_caliper_inputs(s);
  std::map<std::string, double> noisy = truth;
  NormalGenerator rng(subject_seed);
  for (const auto& [name, mae] : table2_mae(opt.noise)) noisy[name] += rng.normal() * gaussian_sd_of_mae(mae);
  const RealToVirtual& maps = builder.model_maps();
  const BodyModel& model = builder.model();

  auto held_out_errors = [&](const std::map<std::string, double>& achieved, const std::vector<std::string>& used,
                             std::map<std::string, double>& errs) {
    for (const auto& [col, m] : held_out_columns()) {
      // A file may lack some ANSUR columns: those comparisons are simply not counted (n says so).
      auto it = achieved.find(m);
      auto truth_it = s.values.find(col);
      errs[col] = it == achieved.end() || truth_it == s.values.end() ? NAN : it->second - truth_it->second;
    }
    for (const auto& [canonical, key] : input_keys()) {
      if (std::find(used.begin(), used.end(), canonical) != used.end()) continue;
      auto it = achieved.find(canonical);
      // A real measurement compares with the avatar through the model's real → virtual map.
      errs[key] = it == achieved.end() ? NAN : it->second - maps.map(canonical).apply(truth.at(canonical));
    }
  };

  std::vector<std::string> methods = opt.regressors;
  const bool r2_evaluated = std::find(methods.begin(), methods.end(), "R2") != methods.end();
  if (opt.baselines && !r2_evaluated) methods.push_back("baseline:R2");
  for (const auto& method : methods) {
    const std::string regressor = method.rfind("baseline:", 0) == 0 ? method.substr(9) : method;
    try {
      AvatarRequest req;
      req.measurements = noisy;
      req.regressor = regressor;
      req.measure_only = measured_names();
      req.noise = opt.map_noise.empty() ? map_noise_for(opt.noise) : opt.map_noise;
      req.vertex_uncertainty = false;
      const Avatar a = builder.build(req);
      if (!a.uncertainty.empty()) {
        // Calibration of the predicted SD: held-out columns against ANSUR, inputs against the
        // noise-free value (through the model's map), each as |error| / SD.
        auto& st = out.standardised[method];
        for (const auto& [col, m] : held_out_columns()) {
          auto it = a.achieved.find(m);
          auto t = s.values.find(col);
          auto u = a.uncertainty.find(m);
          if (it != a.achieved.end() && t != s.values.end() && u != a.uncertainty.end() && u->second > 0)
            st[col] = {std::abs(it->second - t->second) / u->second, u->second};
        }
        for (const auto& [canonical, key] : input_keys()) {
          auto it = a.achieved.find(canonical);
          auto u = a.uncertainty.find(canonical);
          if (it != a.achieved.end() && u != a.uncertainty.end() && truth.count(canonical) && u->second > 0)
            st[key] = {std::abs(it->second - maps.map(canonical).apply(truth.at(canonical))) / u->second, u->second};
        }
      }
      for (const auto& in : a.inputs) {
        const auto key = std::find_if(input_keys().begin(), input_keys().end(), [&](auto& k) { return k.first == in; });
        const std::string k = key == input_keys().end() ? in : key->second;
        out.inputs[method][k] = a.achieved.at(in) - a.targets.at(in);
        if (truth.count(in)) out.inputs_vs_truth[method][k] = a.achieved.at(in) - maps.map(in).apply(truth.at(in));
      }
      held_out_errors(a.achieved, a.inputs, out.held_out[method]);
      // A body moved back inside the population counts as implausible: its inputs were not.
      out.implausible[method] = a.plausibility.overall == Verdict::Implausible || a.noise_widened > 1;
    } catch (const Error&) {
      out.failed[method] = true;
    }
  }
  if (opt.baselines && r2_evaluated) {  // the R2 baseline is the R2 regressor: computed once
    if (out.failed.count("R2")) out.failed["baseline:R2"] = true;
    if (out.inputs.count("R2")) out.inputs["baseline:R2"] = out.inputs["R2"];
    if (out.inputs_vs_truth.count("R2")) out.inputs_vs_truth["baseline:R2"] = out.inputs_vs_truth["R2"];
    if (out.held_out.count("R2")) out.held_out["baseline:R2"] = out.held_out["R2"];
    if (out.implausible.count("R2")) out.implausible["baseline:R2"] = out.implausible["R2"];
  }
  // The linear limit of each method, from the same noisy inputs.
  std::vector<std::string> all_methods = methods;
  if (opt.baselines) all_methods.push_back("baseline:uniform_scale");
  if (opt.baselines && r2_evaluated) all_methods.push_back("baseline:R2");
  for (const auto& method : all_methods)
    if (const LinearLimit* limit = limits(method))
      for (const auto& [col, m] : held_out_columns())
        if (auto t = s.values.find(col); t != s.values.end()) out.linear[method][col] = limit->predict(col, noisy) - t->second;
  if (opt.baselines) {
    // The mean body scaled uniformly (about the floor centre) to the subject's stature.
    const Vertices& mean = mean_body;
    const double mean_stature = measure(model, *model.find_measurement("stature"), mean);
    const Vertices scaled = mean * (noisy.at("stature") / mean_stature);
    const std::map<std::string, double> achieved = measure_some(model, measured_names(), scaled);
    out.inputs["baseline:uniform_scale"]["stature"] = achieved.at("stature") - noisy.at("stature");
    held_out_errors(achieved, {"stature"}, out.held_out["baseline:uniform_scale"]);
    out.implausible["baseline:uniform_scale"] = false;
  }
}

constexpr int kLinearFolds = 10;

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ",") + n;
  return out;
}

// Linear limits by (sex, inputs, fold): one fit per sex and input set on the training file, or
// one per fold for cross-validation (fold f is fitted on the same sex's subjects outside it).
using LinearLimits = std::map<std::tuple<Sex, std::string, int>, LinearLimit>;

LinearLimits fit_linear_limits(const std::vector<AnsurSubject>& subjects, const EvaluationOptions& opt) {
  std::vector<std::string> methods = opt.regressors;
  if (opt.baselines) { methods.push_back("baseline:uniform_scale"); methods.push_back("baseline:R2"); }
  std::vector<std::string> columns;
  for (const auto& entry : held_out_columns()) {
    const std::string& col = entry.first;  // not a structured binding: clang 14 cannot capture one
    if (std::any_of(subjects.begin(), subjects.end(), [&](const AnsurSubject& s) { return s.values.count(col) > 0; }))
      columns.push_back(col);
  }
  LinearLimits limits;
  if (columns.empty()) return limits;
  std::set<Sex> sexes;
  for (const auto& s : subjects) sexes.insert(s.sex);
  for (Sex sex : sexes)
    for (const auto& method : methods) {
      const std::vector<std::string> inputs = method_inputs(method);
      const int folds = opt.linear_training ? 1 : kLinearFolds;
      for (int f = 0; f < folds; ++f) {
        const auto key = std::make_tuple(sex, joined(inputs), f);
        if (limits.count(key)) continue;
        std::vector<const AnsurSubject*> training;
        const std::vector<AnsurSubject>& pool = opt.linear_training ? *opt.linear_training : subjects;
        for (size_t i = 0; i < pool.size(); ++i)
          if (pool[i].sex == sex && (opt.linear_training || static_cast<int>(i % kLinearFolds) != f)) training.push_back(&pool[i]);
        try {
          limits.emplace(key, LinearLimit(training, inputs, columns));
        } catch (const Error&) {
          // Too few people of this sex to fit it (a small file): no limit, no ratios, said below.
        }
      }
    }
  return limits;
}

// Ratios of a method's held-out MAE to its linear limit's, and their median and worst.
void compare_with_linear(MethodEvaluation& me) {
  std::vector<std::pair<double, std::string>> ratios;
  for (const auto& [col, m] : held_out_columns()) {
    auto a = me.held_out.find(col);
    auto l = me.linear_limit.find(col);
    if (a == me.held_out.end() || l == me.linear_limit.end() || l->second.mae <= 0) continue;
    me.ratio_to_linear[col] = a->second.mae / l->second.mae;
    ratios.emplace_back(me.ratio_to_linear[col], col);
  }
  if (ratios.empty()) return;
  std::sort(ratios.begin(), ratios.end());
  const size_t n = ratios.size();
  me.ratio_median = n % 2 ? ratios[n / 2].first : (ratios[n / 2 - 1].first + ratios[n / 2].first) / 2;
  me.ratio_worst = ratios.back().first;
  me.ratio_worst_column = ratios.back().second;
}

}  // namespace

std::vector<std::string> method_inputs(const std::string& method) {
  if (method == "baseline:uniform_scale") return {"stature"};
  const std::string name = method.rfind("baseline:", 0) == 0 ? method.substr(9) : method;
  std::string upper = name;
  for (auto& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (upper == "AUTO" || upper == "MAP") {
    std::vector<std::string> all;
    for (const auto& [canonical, key] : input_keys()) all.push_back(canonical);
    return all;
  }
  return preset_inputs(upper);
}

Evaluation evaluate_subjects(const std::vector<AnsurSubject>& subjects,
                             const std::function<std::shared_ptr<const AvatarBuilder>(Sex)>& builder_for,
                             const EvaluationOptions& opt) {
  for (const auto& r : opt.regressors) {
    std::string upper = r;
    for (auto& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (upper != "AUTO" && upper != "MAP") preset_inputs(upper);  // unknown names fail before any work
  }
  if (!opt.map_noise.empty()) parse_noise_setting(opt.map_noise);
  const int n = static_cast<int>(subjects.size());
  // Builders are fetched (and their regressors trained) before the workers start.
  std::map<Sex, std::shared_ptr<const AvatarBuilder>> builders;
  std::map<Sex, Vertices> means;
  for (const auto& s : subjects)
    if (!builders.count(s.sex)) {
      builders[s.sex] = builder_for(s.sex);
      means[s.sex] = builders[s.sex]->model().rest_vertices(Eigen::VectorXd());
    }
  const LinearLimits limits = fit_linear_limits(subjects, opt);
  std::vector<SubjectErrors> per(static_cast<size_t>(n));
  const std::vector<std::string> errors = detail::parallel_for(
      n, opt.threads,
      [&](int i) {
        const Sex sex = subjects[static_cast<size_t>(i)].sex;
        const int fold = opt.linear_training ? 0 : i % kLinearFolds;
        const LimitsFor limits_for = [&](const std::string& method) -> const LinearLimit* {
          auto it = limits.find({sex, joined(method_inputs(method)), fold});
          return it == limits.end() ? nullptr : &it->second;
        };
        evaluate_one(subjects[static_cast<size_t>(i)], *builders.at(sex), means.at(sex), opt,
                     opt.seed * 1000003ULL + static_cast<std::uint64_t>(i), limits_for, per[static_cast<size_t>(i)]);
      },
      opt.progress);
  for (int i = 0; i < n; ++i)
    if (!errors[static_cast<size_t>(i)].empty())
      throw Error(ErrorKind::Format, "subject " + subjects[static_cast<size_t>(i)].id + ": " + errors[static_cast<size_t>(i)], "subjects");

  Evaluation ev;
  ev.subjects = n;
  ev.linear_limit_fitted_on = opt.linear_training
                                  ? std::to_string(opt.linear_training->size()) + " training subjects"
                                  : "10-fold cross-validation over the evaluated subjects (subject i left out in fold i mod 10)";
  if (limits.empty()) ev.linear_limit_fitted_on = "not fitted: the file has none of the held-out columns, or too few subjects of a sex (a fit needs the inputs + 2)";
  ev.noise = opt.noise;
  ev.seed = opt.seed;
  std::vector<std::string> methods = opt.regressors;
  if (opt.baselines) { methods.push_back("baseline:uniform_scale"); methods.push_back("baseline:R2"); }
  for (const auto& method : methods) {
    MethodEvaluation me;
    std::map<std::string, std::vector<double>> in, in_truth, out;
    int implausible = 0, built = 0;
    for (const auto& p : per) {
      if (p.failed.count(method)) { ++me.failures; continue; }
      ++built;
      if (p.implausible.count(method) && p.implausible.at(method)) ++implausible;
      if (p.inputs.count(method)) for (const auto& [k, e] : p.inputs.at(method)) in[k].push_back(e);
      if (p.inputs_vs_truth.count(method)) for (const auto& [k, e] : p.inputs_vs_truth.at(method)) in_truth[k].push_back(e);
      if (p.held_out.count(method)) for (const auto& [k, e] : p.held_out.at(method)) out[k].push_back(e);
    }
    for (const auto& [k, v] : in) me.inputs[k] = stats_of(v);
    for (const auto& [k, v] : in_truth) me.inputs_vs_truth[k] = stats_of(v);
    std::map<std::string, std::vector<std::pair<double, double>>> standardised;
    for (const auto& p : per)
      if (auto it = p.standardised.find(method); it != p.standardised.end() && !p.failed.count(method))
        for (const auto& [k, zs] : it->second) standardised[k].push_back(zs);
    for (const auto& [k, v] : standardised) {
      Calibration c;
      for (const auto& [z, sd] : v) {
        c.within_1sd += z <= 1;
        c.within_2sd += z <= 2;
        c.mean_sd += sd;
      }
      c.count = static_cast<int>(v.size());
      c.within_1sd /= c.count;
      c.within_2sd /= c.count;
      c.mean_sd /= c.count;
      me.calibration[k] = c;
    }
    for (const auto& [k, v] : out)
      if (ErrorStats st = stats_of(v); st.count > 0) me.held_out[k] = st;  // columns the file lacks are left out
    std::map<std::string, std::vector<double>> linear;
    for (const auto& p : per)
      if (auto it = p.linear.find(method); it != p.linear.end() && !p.failed.count(method))
        for (const auto& [k, e] : it->second) linear[k].push_back(e);
    for (const auto& [k, v] : linear) me.linear_limit[k] = stats_of(v);
    compare_with_linear(me);
    me.implausible_share = built ? static_cast<double>(implausible) / built : 0;
    if (method.rfind("baseline:", 0) == 0) ev.baselines[method.substr(9)] = me;
    else ev.regressors[method] = me;
  }
  return ev;
}

std::string evaluation_json(const Evaluation& ev, int indent) {
  using nlohmann::ordered_json;
  auto method_json = [](const MethodEvaluation& me) {
    ordered_json j;
    j["inputs"] = ordered_json::object();
    for (const auto& [k, s] : me.inputs) {
      const bool kg = k == "weight";
      const double f = kg ? 1 : 100;
      const std::string u = kg ? "_kg" : "_cm";
      j["inputs"][k] = {{"mae" + u, s.mae * f}, {"max" + u, s.max * f}, {"bias" + u, s.bias * f}, {"n", s.count}};
    }
    j["inputs_vs_truth"] = ordered_json::object();
    for (const auto& [k, s] : me.inputs_vs_truth) {
      const bool kg = k == "weight";
      const double f = kg ? 1 : 100;
      const std::string u = kg ? "_kg" : "_cm";
      j["inputs_vs_truth"][k] = {{"mae" + u, s.mae * f}, {"max" + u, s.max * f}, {"bias" + u, s.bias * f}, {"n", s.count}};
    }
    j["held_out"] = ordered_json::object();
    for (const auto& [k, s] : me.held_out) {
      const bool kg = k == "weight";
      const double f = kg ? 1 : 100;
      const std::string u = kg ? "_kg" : "_cm";
      j["held_out"][k] = {{"mae" + u, s.mae * f}, {"bias" + u, s.bias * f}, {"max" + u, s.max * f}, {"n", s.count}};
    }
    j["implausible_share"] = me.implausible_share;
    j["failures"] = me.failures;
    if (!me.linear_limit.empty()) {
      j["linear_limit"] = ordered_json::object();
      for (const auto& [k, s] : me.linear_limit) j["linear_limit"][k] = {{"mae_cm", s.mae * 100}, {"n", s.count}};
      j["ratio_to_linear"] = me.ratio_to_linear;
      if (!me.ratio_to_linear.empty()) {
        j["ratio_to_linear_median"] = me.ratio_median;
        j["ratio_to_linear_worst"] = {{"column", me.ratio_worst_column}, {"ratio", me.ratio_worst}};
      }
    }
    if (!me.calibration.empty()) {
      j["calibration"] = ordered_json::object();
      for (const auto& [k, c] : me.calibration) {
        const bool kg = k == "weight";
        j["calibration"][k] = {{"within_1sd", c.within_1sd}, {"within_2sd", c.within_2sd},
                               {kg ? "mean_sd_kg" : "mean_sd_cm", c.mean_sd * (kg ? 1 : 100)}, {"n", c.count}};
      }
    }
    return j;
  };
  ordered_json j;
  j["subjects"] = ev.subjects;
  j["noise"] = to_string(ev.noise);
  j["seed"] = ev.seed;
  j["linear_limit"] = {{"fitted_on", ev.linear_limit_fitted_on},
                       {"method", "least squares from each method's own inputs (noise-free training values) to each held-out column"}};
  j["regressors"] = ordered_json::object();
  for (const auto& [name, me] : ev.regressors) j["regressors"][name] = method_json(me);
  j["baselines"] = ordered_json::object();
  for (const auto& [name, me] : ev.baselines) j["baselines"][name] = method_json(me);
  return j.dump(indent) + "\n";
}

std::map<std::string, SurfaceStats> synthetic_surface_study(const AvatarBuilder& builder,
                                                            const std::vector<std::string>& regressors,
                                                            MeasurementNoise noise, int bodies, std::uint64_t seed) {
  if (bodies < 1 || bodies > 100000) throw Error(ErrorKind::OutOfRange, "bodies must be in [1, 100000]", "bodies");
  const BodyModel& model = builder.model();
  NormalGenerator rng(seed);
  // Align as the paper does: common floor, bounding boxes centred in x and z.
  auto align = [](Vertices v) {
    const Eigen::RowVector3d lo = v.colwise().minCoeff(), hi = v.colwise().maxCoeff();
    v.col(0).array() -= (lo.x() + hi.x()) / 2;
    v.col(2).array() -= (lo.z() + hi.z()) / 2;
    v.col(1).array() -= lo.y();
    return v;
  };
  std::map<std::string, SurfaceStats> out;
  std::vector<std::string> inputs = {"stature", "weight", "span", "crotch_height", "hip_breadth", "arm_length"};
  for (int b = 0; b < bodies; ++b) {
    Eigen::VectorXd beta(model.shape_count());
    for (auto& x : beta) x = rng.normal();
    const Vertices truth = align(model.rest_vertices(beta));
    std::map<std::string, double> m;
    for (const auto& name : inputs) m[name] = measure(model, *model.find_measurement(name), truth);
    // The synthetic person's "real" measurements are the virtual ones: no real → virtual map.
    for (const auto& [name, mae] : table2_mae(noise)) m[name] += rng.normal() * gaussian_sd_of_mae(mae);
    for (const auto& r : regressors) {
      AvatarRequest req;
      req.measurements = m;
      req.regressor = r;
      req.apply_model_maps = false;
      req.measure_only = {"stature"};
      req.noise = map_noise_for(noise);
      req.vertex_uncertainty = false;
      const Vertices rebuilt = align(builder.build(req).rest_vertices);
      const Eigen::VectorXd dist = (rebuilt - truth).rowwise().norm();
      SurfaceStats& s = out[r];
      s.mean_cm += dist.mean() * 100 / bodies;
      s.max_cm += dist.maxCoeff() * 100 / bodies;
      s.worst_cm = std::max(s.worst_cm, dist.maxCoeff() * 100);
    }
  }
  return out;
}

}  // namespace caliper
