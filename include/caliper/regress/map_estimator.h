// The noise-aware estimator "map" (goes beyond the paper's §3.4.3 regressors): the
// maximum a posteriori shape β given any subset of known measurements, under the model's prior
// β ~ N(0, I) and independent Gaussian measurement noise,
//     β̂ = argmin  Σ_i ((m_i(β) − y_i) / σ_i)² + ‖β‖²,
// found by Levenberg–Marquardt on the measurement functions linearised exactly (measure_with_gradient).
// The posterior is approximated by the Gaussian at β̂ (Laplace): Σ = (Jᵀ W J + I)⁻¹, W = diag(σ⁻²),
// from which every measurement's SD (√(g Σ gᵀ)) and every vertex's SD follow.
// Consistent, nearly noise-free inputs are reproduced (σ → 0 makes them constraints); noisy or
// contradictory inputs are reconciled by the prior instead of pushing β out of the population
// (the failure of R6 with self-measurements, paper Fig. 9). For self/other noise each input may
// also be a gross error (2 %, 10σ wide): an input the others contradict by several SD is then
// weighed down (EM on leave-one-out responsibilities) rather than bending the whole body.
#pragma once
#include <Eigen/Core>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "caliper/body/body_model.h"
#include "caliper/body/volume_polynomial.h"

namespace caliper {

// Who took the measurements, which sets the default noise:
//   Self / Other: paper Table 2 (Virtual Caliper, self- or other-measured) where it has an entry,
//                 the documented defaults of default_noise_sd() elsewhere;
//   Exact:        a tiny noise floor (0.1 mm, 10 g): inputs are reproduced like the regressors do.
enum class NoiseSetting { Exact, Self, Other };
NoiseSetting parse_noise_setting(const std::string& text);  // exact | self | other; throws Error(InvalidArgument)
const char* to_string(NoiseSetting setting);

// Paper Table 2 (vocabulary/noise.h) as standard deviations (metres): MAE·√(π/2), the SD of a
// zero-mean Gaussian with that mean absolute error. Entries: stature, span, arm_length, crotch_height, hip_breadth.
// Empty for Exact.
std::map<std::string, double> table2_sd(NoiseSetting setting);

// Default noise SD (SI: m, kg) of a measurement the model defines, under a setting:
//   Table 2 entries as above; weight 1.0 kg (bathroom scale plus day-to-day variation);
//   other heights 1.5 cm, other lengths and spans 1.5 cm, breadths and depths 1.0 cm (caliper-like
//   VR widths, cf. hip width's 0.8 cm in Table 2), circumferences 1.5 cm self / 1.0 cm other
//   (tape measure; ISAK's girth errors are ~1 %); Exact: 0.1 mm and 0.01 kg.
// Throws Error(Unsupported) if the model does not define the measurement.
double default_noise_sd(const BodyModel& model, const std::string& measurement, NoiseSetting setting);

struct MapOptions {
  NoiseSetting noise = NoiseSetting::Self;
  std::map<std::string, double> noise_sd;  // per-measurement overrides, SI (m, kg), each > 0
  // Measurements whose posterior SD is wanted (empty: every measurement the model defines).
  std::vector<std::string> uncertainty_of;
  bool measurement_uncertainty = true;     // false: skip measurement SDs (saves measuring them all)
  bool vertex_uncertainty = true;          // per-vertex SD
  int max_iterations = 50;                 // Levenberg–Marquardt iterations per solve
  // Share of inputs assumed to be gross errors (10σ wide) for self/other noise; 0 = pure Gaussian.
  double gross_error_rate = 0.02;
  double warn_sd = 3.0;                    // warn when a standardised residual exceeds this
  // Whether a shape is inside the population (empty: no bound). When the inputs call for a body
  // outside it (e.g. BMI 40 on a model of soldiers), every input's noise SD is widened by one
  // common factor, the least that brings β̂ inside: the closest body the population holds,
  // weighed as the inputs were, with a warning saying so.
  std::function<bool(const Eigen::VectorXd& beta)> within_population;
  // How a person reads a value of a measurement (SI → SI), for the words only: warnings say a
  // value the model takes in another posture (arm length through a real → virtual map, paper
  // §3.3) as it was measured. Empty: as the model measures it. `inputs` stay in the model's terms.
  std::function<double(const std::string& name, double value)> as_measured;
};

struct MapInputFit {
  double value = 0;         // y, SI
  double noise_sd = 0;      // σ, SI (as given or by default)
  double effective_sd = 0;  // σ after the gross-error stage (> σ when the input looks like a blunder)
  double fitted = 0;        // m(β̂), SI
  double expected = 0;      // what the other inputs predict for it (leave-one-out, linearised), SI
  double expected_sd = 0;   // SD of that prediction, SI
  double z = 0;             // (y − expected) / √(σ² + expected_sd²): N(0, 1) if consistent
  // What the model's population has for it (the model linearised at its mean body), SI, and
  // where the value stands there: (value − population_mean) / population_sd.
  double population_mean = 0, population_sd = 0, population_z = 0;
};

struct MapEstimate {
  Eigen::VectorXd beta;                          // K
  Eigen::MatrixXd covariance;                    // K×K posterior covariance of β
  std::map<std::string, MapInputFit> inputs;     // per input measurement
  std::map<std::string, double> measurement_sd;  // posterior SD per measurement, SI (m, kg)
  Eigen::VectorXd vertex_sd;                     // N, √trace of each vertex's 3×3 covariance, metres
  std::vector<std::string> warnings;             // plain words, the culprit named first
  int iterations = 0;                            // Levenberg–Marquardt iterations, all solves
  bool converged = false;
  // > 1 when the inputs lay outside the population (MapOptions::within_population): the factor
  // their noise SDs were widened by to reach the closest body inside it.
  double noise_widened = 1;
};

// What makes a body unusual, in plain words, the strongest first: inputs 2 SD or more from the
// population's average ("stature 160.0 cm is 2.6 SD below the population's average (162.9 cm)")
// and inputs the others contradict ("span 200.0 cm is 4.2 SD longer than the other
// measurements suggest (182.4 cm)"). Empty when nothing stands out.
// `as_measured` as in MapOptions.
std::vector<std::string> describe_drivers(const BodyModel& model, const std::map<std::string, MapInputFit>& fits,
                                          const std::function<double(const std::string&, double)>& as_measured = {});

// Holds what is fixed per model (its measurements, linearised at the mean body on first use);
// const and thread-safe.
class MapEstimator {
 public:
  explicit MapEstimator(std::shared_ptr<const BodyModel> model);
  const BodyModel& model() const { return *model_; }

  // `values`: canonical name → SI value (weight in kg), at least one. Throws Error(Unsupported)
  // naming a measurement the model lacks, Error(InvalidArgument) for a non-finite value or a
  // non-positive noise override.
  MapEstimate estimate(const std::map<std::string, double>& values, const MapOptions& options = {}) const;

 private:
  struct Linearisation {
    Eigen::VectorXd m0;  // every measurement at β = 0 (order of all_measurements_), SI
    Eigen::MatrixXd j0;  // their Jacobian there
  };
  const Linearisation& at_mean() const;  // computed once, thread-safe
  // The body's volume as a cubic in β, for the weight at every step; worked out once, thread-safe.
  // Null for a model with more than 64 shape directions (the weight is then measured on the mesh).
  const VolumePolynomial* volume() const;
  // One MAP solve with the given options (no population bound).
  MapEstimate solve(const std::map<std::string, double>& values, const MapOptions& options) const;
  // Re-solves with every input's noise widened until β̂ is within the population.
  MapEstimate solve_within_population(const std::map<std::string, double>& values, const MapOptions& options,
                                      const MapEstimate& unbounded) const;

  std::shared_ptr<const BodyModel> model_;
  std::vector<std::string> all_measurements_;
  mutable std::once_flag mean_once_;
  mutable Linearisation mean_;
  mutable std::once_flag volume_once_;
  mutable std::unique_ptr<VolumePolynomial> volume_;
};

}  // namespace caliper
