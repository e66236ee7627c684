// Choosing K, the number of shape directions of a population-built model, by held-out
// validation: the subjects are split into folds; for each fold a model is built from the other
// folds' bodies (PCA with the largest K asked, then truncated, as PCA directions are nested) and
// judged on the fold's subjects, who were not in its population:
//   - how well the K directions reproduce their generated bodies (vertex RMS after projection);
//   - how well the default estimator, given their six Virtual Caliper inputs, predicts the
//     ANSUR II columns it was not given (held_out_columns() of evaluate.h), and how many of
//     those avatars are implausible.
// Every subject is judged exactly once, by the model of the folds it was not in.
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "caliper/io/ansur.h"

namespace caliper {

struct ShapeCountOptions {
  std::vector<int> counts = {5, 10, 15, 20, 25, 30, 40, 50, 60};  // K values to judge (1..64)
  int folds = 2;                // subject i is in fold i mod folds (file order)
  std::string estimator = "auto";  // the regressor the avatars are built with
  int threads = 2;
  std::uint64_t seed = 20121;   // the PCA's randomized range finder, as the model build
  // Optional, from the calling thread: what is being done, and how far.
  std::function<void(const std::string& stage, int done, int total)> progress;
};

struct ShapeCountPoint {
  int k = 0;
  double explained = 0;            // share of the training bodies' variance the K directions keep (fold mean)
  double reconstruction_mm = 0;    // RMS vertex distance of held-out bodies to their K-direction projection, mm
  std::map<std::string, double> held_out_mae;  // ANSUR column → MAE of the avatars (SI: m; weight kg)
  double mean_held_out_mae_cm = 0;  // mean of held_out_mae over the length columns, cm
  double implausible_share = 0;     // share of held-out subjects whose avatar is implausible
  int failures = 0;                 // subjects the estimator could not build
};

// Throws Error(InvalidArgument / OutOfRange) for bad options and Error(Format) when a fold has
// fewer training subjects than the largest K + 1.
std::vector<ShapeCountPoint> validate_shape_counts(const std::vector<AnsurSubject>& subjects, Sex sex,
                                                   const ShapeCountOptions& options = {});

}  // namespace caliper
