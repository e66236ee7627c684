// Linear regressors from measurements to shape parameters (paper §3.4.3).
#include "caliper/regress/regressor.h"

#include <Eigen/QR>
#include <algorithm>
#include <atomic>
#include <thread>
#include <cmath>
#include <sstream>

#include "caliper/errors.h"
#include "caliper/measure/geometry.h"
#include "caliper/measure/measure.h"

namespace caliper {

const std::vector<std::string>& preset_names() {
  static const std::vector<std::string> names = {"R2", "R4", "R5", "R6"};
  return names;
}

std::vector<std::string> preset_inputs(const std::string& preset) {
  std::string p = preset;
  for (auto& ch : p) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
  if (p == "R2") return {"stature", "weight"};
  if (p == "R4") return {"stature", "weight", "span", "crotch_height"};
  if (p == "R5") return {"stature", "weight", "span", "crotch_height", "hip_breadth"};
  if (p == "R6") return {"stature", "weight", "span", "crotch_height", "hip_breadth", "arm_length"};
  throw Error(ErrorKind::InvalidArgument, "unknown regressor '" + preset + "' (R2, R4, R5, R6, auto, map, or a comma list of measurements)", "regressor");
}

namespace {

// The weight feature: cube root of the volume is linear in β (§3.4.2), weight is not.
double volume_feature(const BodyModel& model, const Vertices& rest) {
  return std::cbrt(std::max(0.0, signed_volume(rest, model.faces())));
}

}  // namespace

CornerDesign build_corner_design(const BodyModel& model, const std::vector<std::string>& measurements,
                                 int corner_shapes) {
  const int k = std::min(model.shape_count(), corner_shapes);
  if (k < 1 || k > 16)
    throw Error(ErrorKind::OutOfRange, "corner shapes must be in [1, 16], got " + std::to_string(k), "corner_shapes");
  std::vector<const MeasurementDefinition*> defs;
  for (const auto& name : measurements) {
    const MeasurementDefinition* d = model.find_measurement(name);
    if (!d) throw Error(ErrorKind::Unsupported, "model '" + model.name() + "' cannot measure '" + name + "'", name);
    defs.push_back(d);
  }
  const Eigen::Index corners = Eigen::Index(1) << k;
  CornerDesign design;
  design.feature_names = measurements;
  design.betas.resize(corners, k);
  design.features.resize(corners, static_cast<Eigen::Index>(defs.size()));
  // Rows follow the Gray code (row r is corner r ^ (r >> 1)): consecutive corners differ in one
  // shape value, so a body is the previous one plus ±4 SD along one direction — one vector
  // update instead of a full T̄ + S·β. Blocks of rows are independent (each starts from a full
  // evaluation), so the result does not depend on how the two workers share them.
  for (Eigen::Index r = 0; r < corners; ++r) {
    const Eigen::Index c = r ^ (r >> 1);
    for (int i = 0; i < k; ++i) design.betas(r, i) = (c >> i) & 1 ? 2.0 : -2.0;  // ±2 SD (paper §3.4.3)
  }
  // Horizontal sections (hip breadth…) only need the faces the plane can cross at some corner:
  // a vertex moves at most 2·Σ|S_k,y| vertically over the corners, and so does the landmark
  // that places the plane. Cutting through that band of faces gives the same loops, faster.
  const Eigen::MatrixXd& dirs = model.data().shape_directions;
  std::vector<Faces> band(defs.size());
  for (size_t m = 0; m < defs.size(); ++m) {
    const auto& def = *defs[m];
    const bool section = def.kind == MeasurementKind::Breadth || def.kind == MeasurementKind::Depth ||
                         def.kind == MeasurementKind::FrontBreadth ||
                         def.kind == MeasurementKind::Circumference;
    if (!section || def.plane_normal != Axis::Y || def.landmarks.empty()) continue;
    const Vertices& t = model.data().template_vertices;
    auto reach = [&](Eigen::Index v) { return 2.0 * dirs.row(3 * v + 1).leftCols(k).cwiseAbs().sum() + 1e-3; };
    const Eigen::Index l = model.landmark(def.landmarks[0]);
    const double lo = t(l, 1) - reach(l), hi = t(l, 1) + reach(l);
    std::vector<Eigen::Index> keep;
    for (Eigen::Index f = 0; f < model.faces().rows(); ++f) {
      double fmin = 1e300, fmax = -1e300;
      for (int c = 0; c < 3; ++c) {
        const Eigen::Index v = model.faces()(f, c);
        fmin = std::min(fmin, t(v, 1) - reach(v));
        fmax = std::max(fmax, t(v, 1) + reach(v));
      }
      if (fmin <= hi && fmax >= lo) keep.push_back(f);
    }
    band[m].resize(static_cast<Eigen::Index>(keep.size()), 3);
    for (size_t i = 0; i < keep.size(); ++i) band[m].row(static_cast<Eigen::Index>(i)) = model.faces().row(keep[i]);
  }
  constexpr Eigen::Index kBlock = 64;
  const Eigen::Index blocks = (corners + kBlock - 1) / kBlock;
  const Eigen::MatrixXd& directions = dirs;
  std::atomic<Eigen::Index> next{0};
  std::vector<std::string> errors(2);
  auto worker = [&](int id) {
    Vertices rest;
    try {
      for (Eigen::Index b = next++; b < blocks; b = next++) {
        for (Eigen::Index r = b * kBlock; r < std::min(corners, (b + 1) * kBlock); ++r) {
          if (r == b * kBlock) {
            model.rest_vertices(design.betas.row(r).transpose(), rest);
          } else {
            int flipped = 0;
            while (!((r >> flipped) & 1)) ++flipped;  // Gray code: bit ctz(r) changes
            Eigen::Map<Eigen::VectorXd> flat(rest.data(), rest.size());
            flat += (design.betas(r, flipped) - design.betas(r - 1, flipped)) * directions.col(flipped);
          }
          for (size_t m = 0; m < defs.size(); ++m)
            design.features(r, static_cast<Eigen::Index>(m)) =
                defs[m]->kind == MeasurementKind::Weight ? volume_feature(model, rest)
                : band[m].rows() > 0                     ? measure(model, *defs[m], rest, band[m])
                                                         : measure(model, *defs[m], rest);
        }
      }
    } catch (const std::exception& e) {
      errors[static_cast<size_t>(id)] = e.what();
      next = blocks;
    }
  };
  std::thread helper(worker, 1);
  worker(0);
  helper.join();
  for (const auto& e : errors)
    if (!e.empty()) throw Error(ErrorKind::Unsupported, "measuring the corner bodies failed: " + e, "corner_design");
  return design;
}

Regressor::Regressor(const CornerDesign& design, std::vector<std::string> inputs, std::string name)
    : name_(std::move(name)), inputs_(std::move(inputs)) {
  if (inputs_.empty()) throw Error(ErrorKind::InvalidArgument, "a regressor needs at least one input", "inputs");
  const Eigen::Index rows = design.features.rows();
  Eigen::MatrixXd x(rows, static_cast<Eigen::Index>(inputs_.size()) + 1);
  for (size_t i = 0; i < inputs_.size(); ++i) {
    auto it = std::find(design.feature_names.begin(), design.feature_names.end(), inputs_[i]);
    if (it == design.feature_names.end())
      throw Error(ErrorKind::Unsupported, "measurement '" + inputs_[i] + "' is not in the corner design", inputs_[i]);
    x.col(static_cast<Eigen::Index>(i)) = design.features.col(it - design.feature_names.begin());
  }
  x.col(x.cols() - 1).setOnes();
  // Least squares β = A·f + c over the corners; Householder QR with column pivoting is
  // deterministic and robust to nearly collinear inputs (e.g. stature and crotch height).
  const Eigen::MatrixXd w = x.colPivHouseholderQr().solve(design.betas);  // (m+1) × K
  A_ = w.topRows(w.rows() - 1).transpose();
  c_ = w.row(w.rows() - 1).transpose();
}

Eigen::VectorXd Regressor::predict(const BodyModel& model, const std::map<std::string, double>& values) const {
  Eigen::VectorXd f(static_cast<Eigen::Index>(inputs_.size()));
  for (size_t i = 0; i < inputs_.size(); ++i) {
    auto it = values.find(inputs_[i]);
    if (it == values.end())
      throw Error(ErrorKind::Unsupported, "regressor " + name_ + " needs '" + inputs_[i] + "'", inputs_[i]);
    if (!std::isfinite(it->second))
      throw Error(ErrorKind::InvalidArgument, inputs_[i] + " must be a finite number", inputs_[i]);
    double v = it->second;
    if (inputs_[i] == "weight") {
      const auto& c = model.data().weight_from_volume;
      const double volume = (v - c.b) / c.a;
      if (volume <= 0) throw Error(ErrorKind::OutOfRange, "weight is too small to give a positive volume", "weight");
      v = std::cbrt(volume);
    }
    f(static_cast<Eigen::Index>(i)) = v;
  }
  return A_ * f + c_;
}

const char* to_string(Verdict verdict) {
  switch (verdict) {
    case Verdict::Plausible: return "plausible";
    case Verdict::Unusual: return "unusual";
    case Verdict::Implausible: return "implausible";
  }
  return "plausible";
}

double chi_square_tail(int k, double x) {
  if (k < 1) throw Error(ErrorKind::InvalidArgument, "chi-square needs at least one degree of freedom", "k");
  if (!(x > 0)) return 1.0;
  if (!std::isfinite(x)) return 0.0;
  // Q(k/2, x/2): for even k, e^{−x/2} Σ_{i<k/2} (x/2)^i / i!; for odd k, erfc(√(x/2)) plus
  // e^{−x/2} Σ_{i<(k−1)/2} (x/2)^{i+½} / Γ(i + 3/2). Terms built by recurrence, in logs-free form.
  const double h = x / 2;
  double sum = 0, term;
  if (k % 2 == 0) {
    term = std::exp(-h);
    for (int i = 0; i < k / 2; ++i) {
      sum += term;
      term *= h / (i + 1);
    }
    return std::min(1.0, sum);
  }
  term = std::exp(-h) * std::sqrt(h) / std::tgamma(1.5);
  for (int i = 0; i < (k - 1) / 2; ++i) {
    sum += term;
    term *= h / (i + 1.5);
  }
  return std::min(1.0, std::erfc(std::sqrt(h)) + sum);
}

namespace {
// "about 1 in 40 people", "rarer than 1 in 1,000 people": how rare a body this far out is.
std::string rarity_words(double tail) {
  std::ostringstream s;
  if (tail >= 0.1) {
    s << "typical: about " << std::min(99, static_cast<int>(std::round(tail * 100)))
      << " in 100 people of that population are further from its average";
  } else if (tail >= 1e-3) {
    const double one_in = 1 / tail;
    const double rounded = one_in < 100 ? std::round(one_in) : std::round(one_in / 10) * 10;
    s << "about 1 in " << static_cast<int>(rounded) << " people of that population is this far from its average";
  } else if (tail >= 1e-6) {
    s << "rarer than 1 in 1,000 people of that population";
  } else {
    s << "rarer than 1 in a million people of that population";
  }
  return s.str();
}
}  // namespace

Plausibility judge_plausibility(const Eigen::VectorXd& beta) {
  Plausibility p;
  p.per_value.resize(static_cast<size_t>(beta.size()));
  std::ostringstream why;
  for (Eigen::Index i = 0; i < beta.size(); ++i) {
    const double a = std::abs(beta(i));
    Verdict v = !std::isfinite(a) || a > 3.0 ? Verdict::Implausible : a > 2.0 ? Verdict::Unusual : Verdict::Plausible;
    p.per_value[static_cast<size_t>(i)] = v;
    if (v != Verdict::Plausible)
      why << (why.tellp() > 0 ? "; " : "") << "shape " << (i + 1) << " is " << (std::round(beta(i) * 100) / 100)
          << " SD from the mean";
  }
  p.mahalanobis_sq = beta.squaredNorm();
  const int k = static_cast<int>(beta.size());
  if (k >= 1) {
    // Two ways to be far out: the whole shape (‖β‖², χ²_K) and one direction alone (max |β_k|,
    // the largest of K standard normals); the smaller share, doubled for asking twice.
    const double joint = std::isfinite(p.mahalanobis_sq) ? chi_square_tail(k, p.mahalanobis_sq) : 0.0;
    const double largest = std::isfinite(p.mahalanobis_sq) ? beta.cwiseAbs().maxCoeff() : INFINITY;
    const double one_direction = 1 - std::pow(1 - std::erfc(largest / std::sqrt(2.0)), k);
    p.tail_probability = std::min(1.0, 2 * std::min(joint, one_direction));
    p.overall = p.tail_probability < 1e-3 ? Verdict::Implausible : p.tail_probability < 1e-2 ? Verdict::Unusual : Verdict::Plausible;
    p.rarity = rarity_words(p.tail_probability);
    if (p.overall != Verdict::Plausible)
      why << (why.tellp() > 0 ? "; " : "") << "the shape as a whole is far from the population (‖β‖² = "
          << std::round(p.mahalanobis_sq * 10) / 10 << "; " << p.rarity << ")";
  }
  p.explanation = why.tellp() > 0 ? why.str() : "every shape value is within 2 SD of the population mean";
  return p;
}

}  // namespace caliper
