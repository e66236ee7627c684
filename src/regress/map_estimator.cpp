// The noise-aware MAP estimator with uncertainty. Method: Gaussian prior β ~ N(0, I)
// of the shape space (paper §3.4.1), Gaussian measurement noise with the paper's Table 2 errors
// (§4.1), the measurement functions of §3.4.2 linearised exactly in β (their vertex gradients
// times the shape directions) and minimised by Levenberg–Marquardt; Laplace approximation of the posterior at the optimum.
#include "caliper/regress/map_estimator.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "caliper/errors.h"
#include "caliper/vocabulary/catalogue.h"
#include "caliper/vocabulary/noise.h"
#include "caliper/measure/measure.h"

namespace caliper {

NoiseSetting parse_noise_setting(const std::string& text) {
  std::string t = text;
  for (auto& c : t) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (t == "exact") return NoiseSetting::Exact;
  if (t == "self") return NoiseSetting::Self;
  if (t == "other") return NoiseSetting::Other;
  throw Error(ErrorKind::InvalidArgument, "noise must be exact, self or other (got '" + text + "')", "noise");
}

const char* to_string(NoiseSetting setting) {
  switch (setting) {
    case NoiseSetting::Exact: return "exact";
    case NoiseSetting::Self: return "self";
    case NoiseSetting::Other: return "other";
  }
  return "self";
}

std::map<std::string, double> table2_sd(NoiseSetting setting) {
  if (setting == NoiseSetting::Exact) return {};
  std::map<std::string, double> sd = paper_table2_mae(setting == NoiseSetting::Self ? MeasuredBy::Self : MeasuredBy::Other);
  for (auto& [name, v] : sd) v = gaussian_sd_of_mae(v);
  return sd;
}

double default_noise_sd(const BodyModel& model, const std::string& measurement, NoiseSetting setting) {
  const MeasurementDefinition* def = model.find_measurement(measurement);
  if (!def) throw Error(ErrorKind::Unsupported, "model '" + model.name() + "' cannot measure '" + measurement + "'", measurement);
  const bool kg = def->kind == MeasurementKind::Weight;
  // The noise floor of "exact" inputs: small enough that they are reproduced to well under a
  // millimetre (as the regressors reproduce theirs), large enough to keep the system well scaled.
  if (setting == NoiseSetting::Exact) return kg ? 0.01 : 1e-4;
  const auto table = table2_sd(setting);
  if (auto it = table.find(measurement); it != table.end()) return it->second;
  switch (def->kind) {
    case MeasurementKind::Weight: return 1.0;
    case MeasurementKind::Height:
    case MeasurementKind::Length: return 0.015;
    case MeasurementKind::Breadth:
    case MeasurementKind::FrontBreadth:
    case MeasurementKind::Depth: return 0.010;
    case MeasurementKind::Circumference: return setting == NoiseSetting::Self ? 0.015 : 0.010;
  }
  return 0.015;
}

MapEstimator::MapEstimator(std::shared_ptr<const BodyModel> model) : model_(std::move(model)) {
  if (!model_) throw Error(ErrorKind::InvalidArgument, "no body model", "model");
  for (const auto& d : model_->data().measurements) all_measurements_.push_back(d.name);
}

// Defined below, with the other helpers.
namespace {
Eigen::MatrixXd measurement_jacobian(const BodyModel& model, const VolumePolynomial* volume, const Eigen::VectorXd& beta,
                                     const Vertices& rest, const std::vector<std::string>& which, Eigen::VectorXd& base);
}

// Its K³ coefficients outgrow the mesh above this many shape directions (an SMPL-X file may carry
// 400: a gigabyte, and each evaluation slower than a pass over the faces); such models weigh the
// mesh at every step instead.
constexpr int kMaxPolynomialShapes = 64;

const VolumePolynomial* MapEstimator::volume() const {
  std::call_once(volume_once_, [this] {
    if (model_->shape_count() <= kMaxPolynomialShapes) volume_ = std::make_unique<VolumePolynomial>(*model_);
  });
  return volume_.get();
}

const MapEstimator::Linearisation& MapEstimator::at_mean() const {
  std::call_once(mean_once_, [this] {
    const Eigen::VectorXd mean = Eigen::VectorXd::Zero(model_->shape_count());
    const Vertices rest = model_->rest_vertices(mean);
    mean_.j0 = measurement_jacobian(*model_, volume(), mean, rest, all_measurements_, mean_.m0);
  });
  return mean_;
}

namespace {

// The weight of the body of β, weight_kg = a·V(β) + b (paper §3.4.2), from the volume polynomial
// rather than a pass over every face; sets `gradient` to ∂weight/∂β if given.
double weight_at(const BodyModel& model, const VolumePolynomial& volume, const Eigen::VectorXd& beta,
                 Eigen::RowVectorXd* gradient) {
  const WeightFromVolume& c = model.data().weight_from_volume;
  const double v = volume.value(beta, gradient);
  if (gradient) *gradient *= c.a;
  return c.weight_kg(v);
}

// `which` measured on the body of β (SI, weight in kg), in the order of `which`: the weight from
// the volume polynomial when there is one, the rest (and else the weight) on its rest vertices
// `rest` = T(β).
Eigen::VectorXd measure_values(const BodyModel& model, const VolumePolynomial* volume, const Eigen::VectorXd& beta,
                               const Vertices& rest, const std::vector<std::string>& which) {
  auto is_weight = [&](const std::string& name) {
    return volume && model.find_measurement(name)->kind == MeasurementKind::Weight;
  };
  std::vector<std::string> on_mesh;
  for (const auto& name : which)
    if (!is_weight(name)) on_mesh.push_back(name);
  const auto measured = measure_some(model, on_mesh, rest);
  Eigen::VectorXd out(static_cast<Eigen::Index>(which.size()));
  for (size_t i = 0; i < which.size(); ++i)
    out(static_cast<Eigen::Index>(i)) = is_weight(which[i]) ? weight_at(model, *volume, beta, nullptr) : measured.at(which[i]);
  return out;
}

// J = ∂m/∂β (|which| × K) at β, whose rest vertices are `rest`; sets `base` = m(β). Vertices are
// linear in β (T(β) = T̄ + Sβ), so each row is the measurement's gradient in the vertices times S:
// exact, and one measuring per measurement instead of K + 1 for finite differences. The weight's
// row is the volume polynomial's gradient (without one, the volume's gradient in every vertex
// through the single-precision directions: BodyModel::shape_gradient).
Eigen::MatrixXd measurement_jacobian(const BodyModel& model, const VolumePolynomial* volume, const Eigen::VectorXd& beta,
                                     const Vertices& rest, const std::vector<std::string>& which, Eigen::VectorXd& base) {
  const int k = model.shape_count();
  const auto m = static_cast<Eigen::Index>(which.size());
  const Eigen::MatrixXd& directions = model.data().shape_directions;
  base.resize(m);
  Eigen::MatrixXd jac = Eigen::MatrixXd::Zero(m, k);
  for (Eigen::Index i = 0; i < m; ++i) {
    const MeasurementDefinition& def = *model.find_measurement(which[static_cast<size_t>(i)]);
    if (volume && def.kind == MeasurementKind::Weight) {
      Eigen::RowVectorXd gradient;
      base(i) = weight_at(model, *volume, beta, &gradient);
      jac.row(i) = gradient;
      continue;
    }
    const MeasurementGradient g = measure_with_gradient(model, def, rest, model.faces());
    base(i) = g.value;
    if (g.dense.size()) jac.row(i) = model.shape_gradient(g.dense);  // the weight, on the mesh
    for (const GradientTerm& term : g.terms)
      jac.row(i).noalias() += term.d.transpose() * directions.middleRows(3 * static_cast<Eigen::Index>(term.vertex), 3);
  }
  return jac;
}

// Words for "the input is larger / smaller than the rest allow".
std::pair<const char*, const char*> comparatives(MeasurementKind kind) {
  switch (kind) {
    case MeasurementKind::Weight: return {"heavier", "lighter"};
    case MeasurementKind::Breadth:
    case MeasurementKind::FrontBreadth: return {"wider", "narrower"};
    case MeasurementKind::Depth: return {"deeper", "shallower"};
    case MeasurementKind::Circumference: return {"larger", "smaller"};
    default: return {"longer", "shorter"};
  }
}


}  // namespace

namespace {
// A value in the words' terms (MapOptions::as_measured), and an SD around `at` likewise.
std::string said(const std::function<double(const std::string&, double)>& as_measured, const std::string& name, double v) {
  return edge_text(name, as_measured ? as_measured(name, v) : v);
}
std::string said_sd(const std::function<double(const std::string&, double)>& as_measured, const std::string& name,
                    double at, double sd) {
  return edge_text(name, as_measured ? std::abs(as_measured(name, at + sd) - as_measured(name, at)) : sd);
}
// What a measurement is compared with in a warning: the other given measurements, named when
// there are one or two (with only stature and weight given, "the other measurements" read as if
// more had been), and the body model's population behind them.
std::vector<std::string> others_than(const std::vector<std::string>& given, const std::string& name) {
  std::vector<std::string> o;
  for (const auto& g : given)
    if (g != name) o.push_back(g);
  return o;
}
// The others in words: one by name, two joined by `pair_joiner`, more as "the other measurements".
std::string in_words(const std::vector<std::string>& o, const char* pair_joiner) {
  if (o.size() == 1) return o[0];
  return o.size() == 2 ? o[0] + pair_joiner + o[1] : "the other measurements";
}
// "… than stature suggests", "… than span and stature suggest", "… than the other measurements suggest".
std::string suggested_by(const std::vector<std::string>& given, const std::string& name) {
  const auto o = others_than(given, name);
  if (o.empty()) return "the body model's population suggests";
  return in_words(o, " and ") + (o.size() == 1 ? " suggests" : " suggest");
}
// "… than stature and the body model's population allow", "… than span, stature and …".
std::string allowed_by(const std::vector<std::string>& given, const std::string& name) {
  const auto o = others_than(given, name);
  if (o.empty()) return "the body model's population allows";
  return in_words(o, ", ") + " and the body model's population allow";
}
}  // namespace

std::vector<std::string> describe_drivers(const BodyModel& model, const std::map<std::string, MapInputFit>& fits,
                                          const std::function<double(const std::string&, double)>& as_measured) {
  constexpr double kNotable = 2.0;
  std::vector<std::string> given;
  for (const auto& [name, fit] : fits) given.push_back(name);
  std::vector<std::pair<double, std::string>> found;
  for (const auto& [name, fit] : fits) {
    const MeasurementDefinition* def = model.find_measurement(name);
    if (!def) continue;
    const auto [more, less] = comparatives(def->kind);
    std::ostringstream s;
    s.setf(std::ios::fixed);
    s.precision(1);
    if (std::abs(fit.population_z) >= kNotable) {
      s << name << " " << said(as_measured, name, fit.value) << " is " << std::abs(fit.population_z) << " SD "
        << (fit.population_z > 0 ? "above" : "below") << " the population's average ("
        << said(as_measured, name, fit.population_mean) << ")";
      found.emplace_back(std::abs(fit.population_z), s.str());
      s.str("");
    }
    if (std::abs(fit.z) >= kNotable) {
      s << name << " " << said(as_measured, name, fit.value) << " is " << std::abs(fit.z) << " SD "
        << (fit.z > 0 ? more : less) << " than " << suggested_by(given, name) << " ("
        << said(as_measured, name, fit.expected) << ")";
      found.emplace_back(std::abs(fit.z), s.str());
    }
  }
  std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::string> out;
  for (auto& f : found) out.push_back(std::move(f.second));
  return out;
}

MapEstimate MapEstimator::estimate(const std::map<std::string, double>& values, const MapOptions& options) const {
  MapEstimate est;
  if (!options.within_population) {
    est = solve(values, options);
  } else {
    // First β alone: a body far outside may be too wrecked to measure everything on.
    MapOptions quick = options;
    quick.measurement_uncertainty = false;
    quick.vertex_uncertainty = false;
    est = solve(values, quick);
    if (!options.within_population(est.beta)) est = solve_within_population(values, options, est);
    else if (options.measurement_uncertainty || options.vertex_uncertainty) est = solve(values, options);
  }
  const Linearisation& lin = at_mean();
  for (auto& [name, fit] : est.inputs) {
    const auto row = std::find(all_measurements_.begin(), all_measurements_.end(), name) - all_measurements_.begin();
    fit.population_mean = lin.m0(row);
    fit.population_sd = lin.j0.row(row).norm();  // β ~ N(0, I): SD of g·β is ‖g‖
    fit.population_z = fit.population_sd > 0 ? (fit.value - fit.population_mean) / fit.population_sd : 0;
  }
  return est;
}

MapEstimate MapEstimator::solve_within_population(const std::map<std::string, double>& values, const MapOptions& options,
                                                  const MapEstimate& unbounded) const {
  // β̂ moves towards the mean as the inputs' noise widens (the prior weighs more): bracket the
  // common factor by quadrupling, then bisect it in logs; the solves inside need no uncertainty.
  MapOptions widened = options;
  widened.measurement_uncertainty = false;
  widened.vertex_uncertainty = false;
  auto with_factor = [&](double factor, const MapOptions& base) {
    MapOptions o = base;
    for (const auto& [name, fit] : unbounded.inputs) o.noise_sd[name] = factor * fit.noise_sd;
    return o;
  };
  auto inside = [&](double factor) {
    try {
      return options.within_population(solve(values, with_factor(factor, widened)).beta);
    } catch (const Error&) {
      return false;  // a body so far out that a section misses it
    }
  };
  double lo = 1, hi = 2;
  while (!inside(hi) && hi < 1e6) { lo = hi; hi *= 4; }
  for (int i = 0; i < 12 && hi / lo > 1.02; ++i) {
    const double mid = std::sqrt(lo * hi);
    (inside(mid) ? hi : lo) = mid;
  }
  MapEstimate est = solve(values, with_factor(hi, options));
  est.noise_widened = hi;
  // Report the inputs' stated noise (the widening is reported once, as the factor).
  for (auto& [name, fit] : est.inputs) {
    fit.noise_sd = unbounded.inputs.at(name).noise_sd;
    fit.effective_sd = std::max(fit.effective_sd, fit.noise_sd);
  }
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(1);
  s << "these measurements together lie outside the population the model was built from: the avatar is the "
       "closest body inside it";
  std::string sep = ", reaching ";
  for (const auto& [name, fit] : est.inputs) {
    const bool kg = model_->find_measurement(name)->kind == MeasurementKind::Weight;
    if (std::abs(fit.fitted - fit.value) <= std::max(fit.noise_sd, kg ? 0.5 : 0.005)) continue;
    s << sep << name << " " << said(options.as_measured, name, fit.fitted) << " (given "
      << said(options.as_measured, name, fit.value) << ")";
    sep = ", ";
  }
  est.warnings.insert(est.warnings.begin(), s.str());
  return est;
}

MapEstimate MapEstimator::solve(const std::map<std::string, double>& values, const MapOptions& options) const {
  const BodyModel& model = *model_;
  if (values.empty()) throw Error(ErrorKind::InvalidArgument, "the map estimator needs at least one measurement", "measurements");
  std::vector<std::string> names;
  Eigen::VectorXd y(static_cast<Eigen::Index>(values.size())), sd(y.size());
  for (const auto& [name, value] : values) {
    if (!model.find_measurement(name))
      throw Error(ErrorKind::Unsupported, "model '" + model.name() + "' cannot measure '" + name + "'", name);
    if (!std::isfinite(value)) throw Error(ErrorKind::InvalidArgument, name + " must be a finite number", name);
    const auto i = static_cast<Eigen::Index>(names.size());
    y(i) = value;
    auto o = options.noise_sd.find(name);
    if (o != options.noise_sd.end()) {
      if (!std::isfinite(o->second) || o->second <= 0)
        throw Error(ErrorKind::InvalidArgument, "the noise SD of " + name + " must be a positive number", name);
      sd(i) = o->second;
    } else {
      sd(i) = default_noise_sd(model, name, options.noise);
    }
    names.push_back(name);
  }
  for (const auto& [name, s] : options.noise_sd)
    if (!values.count(name) && !(std::isfinite(s) && s > 0))
      throw Error(ErrorKind::InvalidArgument, "the noise SD of " + name + " must be a positive number", name);
  if (options.max_iterations < 1)
    throw Error(ErrorKind::OutOfRange, "max_iterations must be at least 1", "max_iterations");

  const int k = model.shape_count();
  const Eigen::Index n = y.size();
  const Eigen::VectorXd w_nominal = sd.array().square().inverse().matrix();  // diag(σ⁻²)
  Eigen::VectorXd w = w_nominal;  // effective weights (the gross-error stage lowers an outlier's)
  // The rest vertices of the β last asked for: a step's Jacobian is taken at the trial just
  // accepted, whose vertices are still here (each T(β) is a pass over every vertex).
  Vertices rest;
  Eigen::VectorXd rest_of;
  bool rest_valid = false;
  auto rest_at = [&](const Eigen::VectorXd& beta) -> const Vertices& {
    if (!rest_valid || rest_of.size() != beta.size() || rest_of != beta) {
      rest_valid = false;  // not until the new vertices are in
      model.rest_vertices(beta, rest);
      rest_of = beta;
      rest_valid = true;
    }
    return rest;
  };

  const VolumePolynomial* body_volume = volume();
  // Measures `which` on the body of β (SI, weight in kg), in the order of `which`.
  auto measure_at = [&](const Eigen::VectorXd& beta, const std::vector<std::string>& which) {
    return measure_values(model, body_volume, beta, rest_at(beta), which);
  };
  auto objective = [&](const Eigen::VectorXd& beta, const Eigen::VectorXd& m) {
    return (m - y).cwiseProduct(w).dot(m - y) + beta.squaredNorm();
  };
  auto jacobian = [&](const Eigen::VectorXd& beta, const std::vector<std::string>& which, Eigen::VectorXd& base) {
    return measurement_jacobian(model, body_volume, beta, rest_at(beta), which, base);
  };

  MapEstimate est;
  Eigen::VectorXd beta = Eigen::VectorXd::Zero(k);
  Eigen::VectorXd m;
  // Levenberg–Marquardt on the objective with the current weights, from the current β.
  auto minimise = [&]() {
    double f = objective(beta, m);
    double lambda = 1e-4;
    bool done = false;
    for (int it = 0; it < options.max_iterations && !done; ++it) {
      ++est.iterations;
      Eigen::VectorXd at_beta;
      const Eigen::MatrixXd jac = jacobian(beta, names, at_beta);
      const Eigen::MatrixXd h = jac.transpose() * w.asDiagonal() * jac + Eigen::MatrixXd::Identity(k, k);
      const Eigen::VectorXd grad = jac.transpose() * w.asDiagonal() * (m - y) + beta;
      bool accepted = false;
      while (!accepted && lambda < 1e10) {
        Eigen::MatrixXd damped = h;
        damped.diagonal() *= 1 + lambda;
        const Eigen::VectorXd step = -damped.ldlt().solve(grad);
        const Eigen::VectorXd trial = beta + step;
        Eigen::VectorXd mt;
        double ft = std::numeric_limits<double>::infinity();
        try {
          mt = measure_at(trial, names);
          ft = objective(trial, mt);
        } catch (const Error&) {
          // A section that misses the body at an extreme trial shape: reject the step.
        }
        if (std::isfinite(ft) && ft <= f) {
          accepted = true;
          const double decrease = f - ft;
          beta = trial;
          m = mt;
          f = ft;
          lambda = std::max(lambda / 10, 1e-9);
          // Converged when the step no longer moves β or the objective.
          // 1e-3 SD moves no vertex by more than ~0.05 mm.
          if (step.norm() < 1e-3 || decrease <= 1e-9 * (1 + f)) done = true;
        } else {
          lambda *= 10;
        }
      }
      if (!accepted) done = true;  // no descent left: at the optimum
    }
    return done;
  };

  // Each input against what the others (and the prior) predict for it, linearised: removing its
  // term moves β̂ by one Newton step, H₋ᵢ⁻¹ gᵢ (mᵢ − yᵢ) wᵢ, with H₋ᵢ = H − gᵢgᵢᵀwᵢ.
  struct LeaveOneOut {
    Eigen::VectorXd expected, variance;  // the others' prediction and its variance, per input
  };
  auto leave_one_out = [&](const Eigen::MatrixXd& jin, const Eigen::VectorXd& fitted) {
    const Eigen::MatrixXd h = jin.transpose() * w.asDiagonal() * jin + Eigen::MatrixXd::Identity(k, k);
    LeaveOneOut loo{Eigen::VectorXd(n), Eigen::VectorXd(n)};
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::VectorXd g = jin.row(i).transpose();
      const Eigen::MatrixXd h_without = h - g * g.transpose() * w(i);
      loo.variance(i) = std::max(0.0, g.dot(h_without.ldlt().solve(g)));
      loo.expected(i) = fitted(i) + loo.variance(i) * (fitted(i) - y(i)) * w(i);
    }
    return loo;
  };

  // Gross errors (a landmark missed, a value typed wrong): each input is, with probability
  // ε (2 % by default), off by a much wider N(0, (10σ)²) instead of N(0, σ²). The posterior under this
  // mixture is approximated EM-style: an input's responsibility for a gross error is judged
  // against the prediction of the *other* inputs (leave-one-out, so an outlier cannot vouch for
  // itself), its weight becomes the expected precision, and β is re-solved. Consistent inputs
  // keep ≈ their full weight; one 6 SD away from the rest is all but set aside, so it cannot
  // drag the body out of the population. Exact inputs are taken as exact (no gross errors).
  const double kGrossRate = options.gross_error_rate, kGrossScale = 10.0;
  if (!(kGrossRate >= 0 && kGrossRate < 0.5))
    throw Error(ErrorKind::OutOfRange, "gross_error_rate must be in [0, 0.5)", "gross_error_rate");
  const bool robust = kGrossRate > 0 && options.noise != NoiseSetting::Exact;
  constexpr double kSettled = 0.05;
  // New weights from the responsibilities at the current fit; returns the largest relative change.
  auto update_weights = [&](const Eigen::MatrixXd& jin, const Eigen::VectorXd& fitted) {
    const LeaveOneOut loo = leave_one_out(jin, fitted);
    Eigen::VectorXd w_new(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double s2 = sd(i) * sd(i), d = y(i) - loo.expected(i);
      const double v_good = s2 + loo.variance(i), v_gross = kGrossScale * kGrossScale * s2 + loo.variance(i);
      // log N(d; 0, v) up to the common constant; the ratio is computed in logs (d may be huge).
      const double l_good = std::log(1 - kGrossRate) - 0.5 * (d * d / v_good + std::log(v_good));
      const double l_gross = std::log(kGrossRate) - 0.5 * (d * d / v_gross + std::log(v_gross));
      const double gross = 1.0 / (1.0 + std::exp(l_good - l_gross));
      w_new(i) = (1 - gross) / s2 + gross / (kGrossScale * kGrossScale * s2);
    }
    // EM has settled when no weight would move by more than 5 %: then the weights stay those β
    // was solved with.
    const double change = (w_new.array() / w.array() - 1).abs().maxCoeff();
    if (change >= kSettled) w = w_new;
    return change;
  };

  // Warm start on the model linearised at the mean body (cached per model): the linear-Gaussian
  // MAP, and its gross-error weights, cost no measuring at all; the nonlinear solve then needs
  // only a step or two.
  {
    const Linearisation& lin = at_mean();
    Eigen::VectorXd m0(n);
    Eigen::MatrixXd j0(n, k);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto pos = std::find(all_measurements_.begin(), all_measurements_.end(), names[static_cast<size_t>(i)]) - all_measurements_.begin();
      m0(i) = lin.m0(pos);
      j0.row(i) = lin.j0.row(pos);
    }
    for (int round = 0; round < 8; ++round) {
      const Eigen::MatrixXd h = j0.transpose() * w.asDiagonal() * j0 + Eigen::MatrixXd::Identity(k, k);
      beta = h.ldlt().solve(j0.transpose() * w.asDiagonal() * (y - m0));
      if (!robust || update_weights(j0, m0 + j0 * beta) < kSettled) break;
    }
    try {
      m = measure_at(beta, names);
    } catch (const Error&) {  // a start so extreme that a section misses the body: start at the mean
      beta.setZero();
      m = measure_at(beta, names);
    }
  }
  est.converged = minimise();

  // The Laplace posterior at β̂, with the inputs and the wanted measurements linearised together;
  // the same Jacobian checks whether the gross-error weights have settled (else: solve again).
  std::vector<std::string> wanted = names;
  if (options.measurement_uncertainty) {
    const auto& extra = options.uncertainty_of.empty() ? all_measurements_ : options.uncertainty_of;
    for (const auto& name : extra)
      if (model.find_measurement(name) && std::find(wanted.begin(), wanted.end(), name) == wanted.end()) wanted.push_back(name);
  }
  Eigen::VectorXd base;
  Eigen::MatrixXd jall;
  for (int round = 0;; ++round) {
    jall = jacobian(beta, wanted, base);
    if (!robust || round == 8 || update_weights(jall.topRows(n), base.head(n)) < kSettled) break;
    est.converged = minimise() && est.converged;
  }
  const Eigen::MatrixXd jin = jall.topRows(n);
  const Eigen::MatrixXd h = jin.transpose() * w.asDiagonal() * jin + Eigen::MatrixXd::Identity(k, k);
  est.beta = beta;
  est.covariance = h.ldlt().solve(Eigen::MatrixXd::Identity(k, k));
  est.covariance = (est.covariance + est.covariance.transpose()) / 2;
  if (options.measurement_uncertainty)
    for (size_t i = 0; i < wanted.size(); ++i) {
      const Eigen::RowVectorXd g = jall.row(static_cast<Eigen::Index>(i));
      est.measurement_sd[wanted[i]] = std::sqrt(std::max(0.0, (g * est.covariance * g.transpose())(0, 0)));
    }

  const LeaveOneOut loo = leave_one_out(jin, base.head(n));
  std::vector<std::pair<double, std::string>> culprits;
  for (Eigen::Index i = 0; i < n; ++i) {
    MapInputFit fit;
    fit.value = y(i);
    fit.noise_sd = sd(i);
    fit.effective_sd = 1.0 / std::sqrt(w(i));
    fit.fitted = base(i);
    fit.expected = loo.expected(i);
    fit.expected_sd = std::sqrt(loo.variance(i));
    fit.z = (fit.value - fit.expected) / std::sqrt(sd(i) * sd(i) + loo.variance(i));
    est.inputs[names[static_cast<size_t>(i)]] = fit;
    if (std::abs(fit.z) > options.warn_sd) culprits.emplace_back(std::abs(fit.z), names[static_cast<size_t>(i)]);
  }
  std::sort(culprits.begin(), culprits.end(), [](const auto& p, const auto& q) { return p.first > q.first; });
  for (size_t c = 0; c < culprits.size(); ++c) {
    const std::string& name = culprits[c].second;
    const MapInputFit& fit = est.inputs.at(name);
    const auto [more, less] = comparatives(model.find_measurement(name)->kind);
    std::ostringstream s;
    s.setf(std::ios::fixed);
    s.precision(1);
    s << (c == 0 ? "" : "also: ") << name << " is " << std::abs(fit.z) << " SD " << (fit.z > 0 ? more : less)
      << " than " << allowed_by(names, name) << " (given "
      << said(options.as_measured, name, fit.value) << (names.size() > 1 ? "; they suggest " : "; it suggests ")
      << said(options.as_measured, name, fit.expected)
      << " ± " << said_sd(options.as_measured, name, fit.expected, fit.expected_sd) << "); the avatar reconciles it at "
      << said(options.as_measured, name, fit.fitted);
    if (fit.effective_sd > 2 * fit.noise_sd) s << ", treating it as a probable measurement error";
    est.warnings.push_back(s.str());
  }
  if (!est.converged)
    est.warnings.push_back("the estimate did not converge in " + std::to_string(options.max_iterations) + " iterations");

  if (options.vertex_uncertainty) {
    // Vertices are linear in β: cov(v) = S_v Σ S_vᵀ; with Σ = L Lᵀ its trace is ‖S_v L‖²_F.
    const Eigen::MatrixXd l = Eigen::LLT<Eigen::MatrixXd>(est.covariance).matrixL();
    const Eigen::MatrixXd p = model.data().shape_directions.leftCols(k) * l;  // 3N×K
    est.vertex_sd.resize(model.vertex_count());
    for (int v = 0; v < model.vertex_count(); ++v) est.vertex_sd(v) = std::sqrt(p.middleRows(3 * v, 3).squaredNorm());
  }
  return est;
}

}  // namespace caliper
