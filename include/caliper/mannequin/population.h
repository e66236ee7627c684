// The built-in body's statistical shape space: one generated body per ANSUR II
// subject, PCA over their vertices, K directions scaled so β ~ N(0, I), and volume → weight
// calibrated on the same subjects (paper §3.4.2's linear fit, redone on ANSUR).
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "caliper/body/body_model.h"
#include "caliper/body/crease.h"
#include "caliper/io/ansur.h"
#include "caliper/mannequin/generator.h"

namespace caliper::mannequin {

constexpr int kMaxComponents = 64;

struct PopulationOptions {
  // K shape directions kept (1..kMaxComponents). 20: the smallest K whose held-out error is
  // within 1 % of the best, for women and men (`caliper model choose-k`, docs/mannequin.md).
  int components = 20;
  int threads = 2;              // bodies are generated in parallel; results do not depend on it
  std::uint64_t seed = 20121;   // for the randomized SVD; fixed so builds are bit-for-bit equal
  std::function<void(int done, int total)> progress;  // optional, called from the main thread
};

struct PopulationReport {
  int subjects = 0;
  std::vector<double> explained_variance;    // share of total variance per kept component
  double total_explained = 0;
  WeightFromVolume fitted;                   // weight = a·volume + b fitted on these subjects
  double weight_mae_fitted_kg = 0;           // MAE of ANSUR weight vs the fit (volume alone)
  double weight_mae_paper_kg = 0;            // same with the paper's CAESAR coefficients
  double weight_bias_paper_kg = 0;           // mean (paper prediction − ANSUR weight)
};

// Shared by every population-built model (the built-in body, the MakeHuman builder):
// PCA of row-stacked bodies (n × 3N, row-major vertices flattened) by a randomized range finder;
// `bodies` is centred in place. Directions are scaled by their standard deviation (β ~ N(0, I))
// and sign-fixed (largest entry positive) so builds are reproducible.
struct PrincipalComponents {
  Eigen::RowVectorXd mean;          // 1 × 3N
  Eigen::MatrixXd directions;       // 3N × k, column c = unit direction · its standard deviation
  std::vector<double> explained;    // share of total variance per kept component
};
// The same bits on any machine running the same build (x86-64, the same compiler flags and Eigen):
// its products use fixed block sizes (src/mannequin/population.cpp). It sets Eigen's process-wide cache sizes while it runs, so no other thread may multiply Eigen
// matrices meanwhile (PCAs themselves wait for one another).
PrincipalComponents principal_components(Eigen::MatrixXd& bodies, int k, std::uint64_t seed);

// weight = a·volume + b fitted by least squares on the subjects (paper §3.4.2), with the MAE of
// the fit and of the paper's CAESAR coefficients for `sex`.
struct WeightCalibration {
  WeightFromVolume fitted;
  double mae_fitted_kg = 0, mae_paper_kg = 0, bias_paper_kg = 0;
};
WeightCalibration calibrate_weight_from_volume(const std::vector<double>& volumes_m3, const std::vector<double>& weights_kg,
                                               Sex sex);

// Real → virtual maps (paper §3.3) for span, crotch height, hip breadth and arm length, fitted
// on a population's bodies (`bodies` centred, row i + `mean` = subject i's rest vertices,
// flattened) against the subjects' ANSUR values. A map is kept where the model misses the real
// value by 2 mm or more on average. Returns the maps' JSON (metadata "real_to_virtual") and a
// line of fit statistics (metadata "real_to_virtual_fits").
struct RealToVirtualFit {
  std::string maps_json;
  std::string fits;
};
RealToVirtualFit fit_real_to_virtual(const BodyModel& provisional, const Eigen::MatrixXd& bodies,
                                     const Eigen::RowVectorXd& mean, const std::vector<const AnsurSubject*>& subjects);

// One generated body per subject of `sex` (Neutral: all subjects, each body generated with its
// own sex): row i of `bodies` is subject i's rest vertices flattened (x0 y0 z0 x1 …, metres),
// `volumes` their enclosed volumes (m³). `subjects` points into the vector it was made from.
struct GeneratedPopulation {
  std::vector<const AnsurSubject*> subjects;
  Eigen::MatrixXd bodies;       // n × 3N
  std::vector<double> volumes;  // n
};
GeneratedPopulation generate_population(const std::vector<AnsurSubject>& subjects, Sex sex, int threads,
                                        const std::function<void(int done, int total)>& progress = {});

// Creases over a generated population (crease.h): per body region, the largest dihedral angle
// over every body, whose body it is, and the median over bodies of each body's own largest (the
// typical body). Regions come from the built-in rig's skin weights. Runs on `threads` workers.
struct RegionCreaseSurvey {
  BodyRegion region = BodyRegion::Torso;
  double max_degrees = 0;
  std::string worst_subject;  // ANSUR subject id of the body with max_degrees
  EdgeBend worst_edge;
  double median_body_max_degrees = 0;
  double max_p99_degrees = 0;  // the largest of the bodies' 99th percentiles
};
std::vector<RegionCreaseSurvey> survey_creases(const GeneratedPopulation& population, int threads);

// A model of the built-in body's topology with `body` as its template and no shape directions:
// enough to measure that one body with the built-in measurement definitions.
BodyModel measuring_model(const Vertices& body, Sex sex);

// How closely a generated population reproduces its subjects' ANSUR values: per fidelity target
// (fidelity_targets()), the signed error's mean (the bias) and largest size over the bodies, and how
// many bodies miss the test's tolerance (3 mm; 1 % for circumferences). Errors in metres;
// circumferences' also as fractions of the ANSUR value. Runs on `threads` workers.
struct TargetFidelity {
  FidelityTarget target;
  double mean_error_m = 0;             // measured − ANSUR, mean over bodies
  double max_abs_error_m = 0;
  double max_abs_error_fraction = 0;   // |measured − ANSUR| / ANSUR, largest
  std::string worst_subject;           // ANSUR subject id of the largest error
  int out_of_tolerance = 0;
  int bodies = 0;
};
std::vector<TargetFidelity> survey_fidelity(const GeneratedPopulation& population, int threads);

// The model of a generated population: PCA (K = options.components), volume → weight, real →
// virtual maps. `population.bodies` is centred in place. Throws Error(Format) if it has fewer
// than K+1 bodies.
BodyModel model_from_population(GeneratedPopulation& population, Sex sex, const PopulationOptions& options,
                                PopulationReport* report = nullptr);

// Builds the model for `sex` from the subjects of that sex (Neutral: all subjects, each body
// generated with its own sex): generate_population, then model_from_population. Throws
// Error(Format) if fewer than K+1 subjects qualify.
BodyModel build_mannequin_model(const std::vector<AnsurSubject>& subjects, Sex sex,
                                const PopulationOptions& options, PopulationReport* report = nullptr);

}  // namespace caliper::mannequin
