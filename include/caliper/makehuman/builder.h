// The MakeHuman body model: for each ANSUR II subject, the MakeHuman sliders that best
// reproduce the subject's dimensions (measured by Caliper's own measurement code), then PCA over
// the fitted bodies as for the built-in body (K = 10 by default), a joint regressor fitted to
// the rig's joint definitions, volume → weight calibrated on the same subjects.
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "caliper/body/body_model.h"
#include "caliper/io/ansur.h"
#include "caliper/makehuman/assets.h"
#include "caliper/makehuman/body.h"

namespace caliper::makehuman {

// The reference body as a model with no shape space (K = 1, a zero direction): the default
// sliders for `sex` (gender 0, 1 or 0.5), T-pose, landmarks, measurements, SMPL skin weights,
// and the paper's volume → weight coefficients. Used to measure bodies during the fit.
BodyModel reference_model(const Assets& assets, Sex sex);

// The dimensions a subject is fitted to: measurement name → ANSUR column(s) summed.
struct FitTarget {
  std::string measurement;             // Caliper definition name, e.g. "waist_circumference"
  std::vector<std::string> columns;    // ANSUR columns whose sum is the target (SI after reading)
  double sigma = 0.01;                 // residual scale, metres or kg
};
const std::vector<FitTarget>& fit_targets();

// How subjects are fitted (docs/makehuman.md): macro gender from the sex, age from `age`
// (years), race weights from `dodrace`; muscle, weight, height, proportions, cup size and every
// measure modifier by a damped Gauss–Newton (Broyden-updated Jacobian) within their ranges,
// with a weak prior towards the default sliders.
struct BuildOptions {
  int components = 10;          // K shape directions kept (1..64)
  int max_subjects = 1000;      // subjects used; more are subsampled evenly (deterministic); 0 = all
  int iterations = 10;          // Gauss–Newton steps per subject
  int threads = 2;              // results do not depend on it
  std::uint64_t seed = 20121;   // randomized PCA
  std::function<void(int done, int total)> progress;  // optional, from the calling thread
};

struct BuildReport {
  int subjects_available = 0;
  int subjects = 0;                          // fitted and used
  std::vector<double> explained_variance;
  double total_explained = 0;
  WeightFromVolume fitted;
  double weight_mae_fitted_kg = 0, weight_mae_paper_kg = 0, weight_bias_paper_kg = 0;
  std::map<std::string, double> fit_mae;     // per fitted measurement, mean |achieved − ANSUR|, SI
  double joint_rms_m = 0;                    // joint regressor vs the rig's joints over the subjects
  std::vector<TargetProblem> problems;       // targets skipped when loading
  std::vector<std::string> failed_subjects;  // ids whose fit threw (left out)
};

// Throws Error(Format) if fewer than K + 1 subjects of `sex` (neutral: all) can be fitted.
BodyModel build_makehuman_model(const Assets& assets, const std::vector<AnsurSubject>& subjects, Sex sex,
                                const BuildOptions& options, BuildReport* report = nullptr);

}  // namespace caliper::makehuman
