// Held-out validation of the number of shape directions K. Method in the header.
#include "caliper/evaluation/shape_count.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "caliper/errors.h"
#include "caliper/evaluation/evaluate.h"
#include "caliper/mannequin/population.h"

namespace caliper {

namespace {

void check(const ShapeCountOptions& options) {
  if (options.counts.empty()) throw Error(ErrorKind::InvalidArgument, "no shape counts to validate", "counts");
  for (int k : options.counts)
    if (k < 1 || k > mannequin::kMaxComponents)
      throw Error(ErrorKind::OutOfRange,
                  "shape counts must be in [1, " + std::to_string(mannequin::kMaxComponents) + "], got " + std::to_string(k),
                  "counts");
  if (options.folds < 2 || options.folds > 10)
    throw Error(ErrorKind::OutOfRange, "folds must be in [2, 10]", "folds");
}

// The rows of `all` in (or not in) fold f.
mannequin::GeneratedPopulation rows_of(const mannequin::GeneratedPopulation& all, int folds, int f, bool in_fold) {
  mannequin::GeneratedPopulation out;
  std::vector<Eigen::Index> rows;
  for (size_t i = 0; i < all.subjects.size(); ++i)
    if ((static_cast<int>(i % static_cast<size_t>(folds)) == f) == in_fold) rows.push_back(static_cast<Eigen::Index>(i));
  out.bodies.resize(static_cast<Eigen::Index>(rows.size()), all.bodies.cols());
  for (size_t r = 0; r < rows.size(); ++r) {
    out.bodies.row(static_cast<Eigen::Index>(r)) = all.bodies.row(rows[r]);
    out.subjects.push_back(all.subjects[static_cast<size_t>(rows[r])]);
    out.volumes.push_back(all.volumes[static_cast<size_t>(rows[r])]);
  }
  return out;
}

// The model with only its first k shape directions (PCA directions are nested).
std::shared_ptr<const BodyModel> truncated(const BodyModel& full, int k) {
  BodyModelData d = full.data();
  d.shape_directions = d.shape_directions.leftCols(k).eval();
  return std::make_shared<const BodyModel>(std::move(d));
}

// Sum over held-out bodies of the squared distance to their projection on the first k directions,
// for every k in `counts`; `centred` rows are bodies minus the model's mean.
std::vector<double> projection_residuals(const Eigen::MatrixXd& centred, const Eigen::MatrixXd& directions,
                                         const std::vector<int>& counts) {
  // Directions are orthogonal with norms = their SDs: an orthonormal basis is each over its norm.
  // The norms are evaluated once: left as an expression inside the product, each column's norm
  // was worked out again for every coefficient (3N times per column).
  const Eigen::VectorXd inverse_norms = directions.colwise().norm().cwiseInverse().transpose();
  const Eigen::MatrixXd basis = directions * inverse_norms.asDiagonal();
  const Eigen::MatrixXd coefficients = centred * basis;  // n × K
  std::vector<double> out;
  const double total = centred.squaredNorm();
  for (int k : counts) {
    // ‖x − P x‖² = ‖x‖² − ‖Bᵀx‖² for an orthonormal B.
    out.push_back(std::max(0.0, total - coefficients.leftCols(k).squaredNorm()));
  }
  return out;
}

}  // namespace

std::vector<ShapeCountPoint> validate_shape_counts(const std::vector<AnsurSubject>& subjects, Sex sex,
                                                   const ShapeCountOptions& options) {
  check(options);
  const int k_max = *std::max_element(options.counts.begin(), options.counts.end());
  auto report = [&](const std::string& stage) {
    return [&options, stage](int done, int total) {
      if (options.progress) options.progress(stage, done, total);
    };
  };
  mannequin::GeneratedPopulation all = mannequin::generate_population(subjects, sex, options.threads, report("generating bodies"));

  const size_t nk = options.counts.size();
  std::vector<ShapeCountPoint> points(nk);
  std::vector<double> residual(nk, 0.0);
  std::vector<std::map<std::string, double>> mae_sum(nk);
  std::vector<std::map<std::string, int>> mae_count(nk);
  std::vector<double> implausible(nk, 0.0);
  Eigen::Index vertices_seen = 0;
  int judged = 0;
  for (int f = 0; f < options.folds; ++f) {
    mannequin::GeneratedPopulation train = rows_of(all, options.folds, f, false);
    mannequin::GeneratedPopulation test = rows_of(all, options.folds, f, true);
    mannequin::PopulationOptions po;
    po.components = k_max;
    po.threads = options.threads;
    po.seed = options.seed;
    mannequin::PopulationReport pr;
    const BodyModel full = mannequin::model_from_population(train, sex, po, &pr);

    const Eigen::Map<const Eigen::RowVectorXd> mean(full.data().template_vertices.data(), test.bodies.cols());
    const Eigen::MatrixXd centred = test.bodies.rowwise() - mean;
    const std::vector<double> res = projection_residuals(centred, full.data().shape_directions, options.counts);
    vertices_seen += centred.rows() * (centred.cols() / 3);

    std::vector<AnsurSubject> fold_subjects;
    for (const AnsurSubject* s : test.subjects) fold_subjects.push_back(*s);
    judged += static_cast<int>(fold_subjects.size());
    for (size_t c = 0; c < nk; ++c) {
      const int k = options.counts[c];
      residual[c] += res[c];
      double kept = 0;
      for (int i = 0; i < k; ++i) kept += pr.explained_variance[static_cast<size_t>(i)];
      points[c].k = k;
      points[c].explained += kept / options.folds;

      auto builder = std::make_shared<const AvatarBuilder>(truncated(full, k));
      EvaluationOptions eo;
      eo.regressors = {options.estimator};
      eo.baselines = false;
      eo.threads = options.threads;
      eo.progress = report("fold " + std::to_string(f + 1) + "/" + std::to_string(options.folds) + ", K = " + std::to_string(k));
      const Evaluation ev = evaluate_subjects(fold_subjects, [&](Sex) { return builder; }, eo);
      const MethodEvaluation& m = ev.regressors.at(options.estimator);
      for (const auto& [col, st] : m.held_out) {
        mae_sum[c][col] += st.mae * st.count;
        mae_count[c][col] += st.count;
      }
      implausible[c] += m.implausible_share * static_cast<double>(fold_subjects.size());
      points[c].failures += m.failures;
    }
  }
  for (size_t c = 0; c < nk; ++c) {
    ShapeCountPoint& p = points[c];
    p.reconstruction_mm = 1000 * std::sqrt(residual[c] / static_cast<double>(vertices_seen));
    p.implausible_share = implausible[c] / judged;
    double lengths = 0;
    int columns = 0;
    for (const auto& [col, sum] : mae_sum[c]) {
      if (mae_count[c][col] == 0) continue;
      p.held_out_mae[col] = sum / mae_count[c][col];
      if (col == "weight") continue;
      lengths += p.held_out_mae[col];
      ++columns;
    }
    p.mean_held_out_mae_cm = columns ? 100 * lengths / columns : 0;
  }
  return points;
}

}  // namespace caliper
