// The built-in body's statistical shape space (issue 3): one generated body per ANSUR II
// subject, PCA over their vertices, K directions scaled so β ~ N(0, I), and volume → weight
// calibrated on the same subjects (paper §3.4.2's linear fit, redone on ANSUR).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "caliper/body/body_model.h"
#include "caliper/io/ansur.h"

namespace caliper::mannequin {

struct PopulationOptions {
  int components = 10;          // K shape directions kept (1..64)
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

// Builds the model for `sex` from the subjects of that sex (Neutral: all subjects, each body
// generated with its own sex). Throws Error(Format) if fewer than K+1 subjects qualify.
BodyModel build_mannequin_model(const std::vector<AnsurSubject>& subjects, Sex sex,
                                const PopulationOptions& options, PopulationReport* report = nullptr);

}  // namespace caliper::mannequin
