// Evaluation (paper §4.2): rebuild real people from their Virtual Caliper inputs and
// compare the avatars with what was measured on them (ANSUR II), per regressor, with optional
// simulated measurement noise (paper Table 2); and a synthetic study of surface distance in the
// spirit of Table 4.
#pragma once
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "caliper/avatar.h"
#include "caliper/io/ansur.h"

namespace caliper {

enum class MeasurementNoise { None, Self, Other };
MeasurementNoise parse_noise(const std::string& text);  // none | self | other; throws Error
const char* to_string(MeasurementNoise noise);

// Paper Table 2 (vocabulary/noise.h) for a simulated setting: mean absolute error of Virtual
// Caliper measurements (metres) of the five measured inputs; empty for None. Simulated as
// zero-mean Gaussian noise with SD = MAE·√(π/2) (gaussian_sd_of_mae).
std::map<std::string, double> table2_mae(MeasurementNoise noise);
// The map estimator's noise setting that matches simulated noise: none → exact, self, other.
std::string map_noise_for(MeasurementNoise noise);

// held_out_columns(): vocabulary/ansur_columns.h (through io/ansur.h).

struct ErrorStats {
  double mae = 0, max = 0, bias = 0;  // SI (m or kg); bias = mean(avatar − truth)
  int count = 0;
};

// How the "map" estimator's predicted SD matches the real errors: the share of subjects whose
// true value lies within ±1 and ±2 predicted SD of the avatar's (a calibrated Gaussian gives
// 68.3 % and 95.4 %), and the mean predicted SD (SI).
struct Calibration {
  double within_1sd = 0, within_2sd = 0, mean_sd = 0;
  int count = 0;
};

struct MethodEvaluation {
  std::map<std::string, ErrorStats> inputs;    // keyed by ANSUR-style name (stature, weight, span, …)
  // The same inputs against the noise-free value (what the person really measures, through the
  // model's real → virtual map): differs from `inputs` only under simulated noise.
  std::map<std::string, ErrorStats> inputs_vs_truth;
  std::map<std::string, ErrorStats> held_out;  // ANSUR columns + inputs the method did not use
  double implausible_share = 0;
  int failures = 0;  // subjects the method could not build (reported, not hidden)
  // The linear limit from this method's own inputs (linear_limit.h), on the same subjects and the
  // same (noisy) inputs, per held-out column; the method's MAE as a ratio to it; and over the
  // held-out columns the median ratio and the worst one.
  std::map<std::string, ErrorStats> linear_limit;
  std::map<std::string, double> ratio_to_linear;
  double ratio_median = 0, ratio_worst = 0;
  std::string ratio_worst_column;
  std::map<std::string, Calibration> calibration;  // "map" only: held-out columns and inputs (vs the noise-free value)
};

struct EvaluationOptions {
  std::vector<std::string> regressors = {"R2", "R4", "R5", "R6"};  // presets, "auto" or "map"
  MeasurementNoise noise = MeasurementNoise::None;
  // The noise setting the "map" estimator assumes (exact | self | other); empty: the simulated
  // noise's own (none → exact, self → self, other → other).
  std::string map_noise;
  std::uint64_t seed = 1;
  int threads = 2;
  bool baselines = true;  // the mean body scaled to the stature, and R2
  // Where the linear limit is fitted: on these people (e.g. `caliper eval --train FILE`), else by
  // 10-fold cross-validation over the evaluated subjects (subject i predicted by a fit on those
  // not in fold i mod 10). Each sex is fitted on its own; fits use noise-free training values.
  const std::vector<AnsurSubject>* linear_training = nullptr;
  std::function<void(int done, int total)> progress;  // called from the calling thread
};

struct Evaluation {
  int subjects = 0;
  MeasurementNoise noise = MeasurementNoise::None;
  std::uint64_t seed = 1;
  std::map<std::string, MethodEvaluation> regressors;
  std::map<std::string, MethodEvaluation> baselines;
  std::string linear_limit_fitted_on;  // "10-fold cross-validation over the evaluated subjects" or "N training subjects"
};

// The inputs a method of the evaluation works from (canonical names): a preset's, all six
// Virtual Caliper inputs for auto and map, stature for the uniformly scaled mean body.
std::vector<std::string> method_inputs(const std::string& method);

// `builder_for(sex)` returns the avatar builder for a subject's sex (kept across calls).
Evaluation evaluate_subjects(const std::vector<AnsurSubject>& subjects,
                             const std::function<std::shared_ptr<const AvatarBuilder>(Sex)>& builder_for,
                             const EvaluationOptions& options);

// The JSON report: {"subjects": n, "regressors": {"R5": {"inputs": {"stature": {"mae_cm",
// "max_cm"}, …, "weight": {"mae_kg", "max_kg"}}, "held_out": {col: {"mae_cm", "bias_cm"}},
// "implausible_share": …, "linear_limit": {col: {"mae_cm", "n"}}, "ratio_to_linear": {col: r},
// "ratio_to_linear_median", "ratio_to_linear_worst": {"column", "ratio"}}}, "baselines": {…},
// "linear_limit": {"fitted_on"}}; "map" also has "calibration": {key: {"within_1sd",
// "within_2sd", "mean_sd_cm" | "mean_sd_kg", "n"}}.
std::string evaluation_json(const Evaluation& evaluation, int indent = 2);

// Synthetic study (Table 4 in spirit): `bodies` bodies drawn from the model's population
// (β ~ N(0, I)), measured virtually, perturbed with the noise, rebuilt by each regressor, and
// compared after the paper's alignment (common floor, bounding boxes centred in x and z) by the
// distance between corresponding vertices (same topology; an upper bound of the surface-to-
// surface distance). "map" assumes the noise setting map_noise_for(noise).
struct SurfaceStats {
  double mean_cm = 0, max_cm = 0;  // mean over bodies of the mean / max vertex distance
  double worst_cm = 0;             // largest vertex distance seen in any body
};
std::map<std::string, SurfaceStats> synthetic_surface_study(const AvatarBuilder& builder,
                                                            const std::vector<std::string>& regressors,
                                                            MeasurementNoise noise, int bodies, std::uint64_t seed);

}  // namespace caliper
