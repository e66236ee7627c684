// PCA shape space of generated ANSUR bodies (SMPL's shape space is learned the same
// way from registered scans, Loper et al. 2015 §3).
#include "caliper/mannequin/population.h"

#include <Eigen/Dense>
#include <algorithm>
#include <atomic>
#include <map>
#include <mutex>
#include <cmath>
#include <sstream>
#include <thread>

#include "caliper/errors.h"
#include "caliper/random.h"
#include "parallel.h"
#include "caliper/mannequin/generator.h"
#include "caliper/measure/geometry.h"
#include "caliper/measure/measure.h"
#include "caliper/protocol/real_to_virtual.h"

namespace caliper::mannequin {

namespace {

// Eigen splits matrix products (and the blocked Householder QR) into blocks sized by the CPU
// caches it detects, and the blocks set the order in which sums are added: on a machine with
// other caches the shape directions came out different in the 16th digit, and the committed
// models did not rebuild bit for bit. The PCA runs with one fixed set of sizes and puts the
// caller's back afterwards. (Same bits wherever the build is the same: x86-64, the same compiler
// flags and Eigen. The sizes are Eigen's process-wide settings: one PCA at a time, and nothing
// else in a model build multiplies matrices meanwhile; principal_components()'s header says so.)
class FixedProductBlocking {
 public:
  FixedProductBlocking() : lock_(mutex()), l1_(Eigen::l1CacheSize()), l2_(Eigen::l2CacheSize()), l3_(Eigen::l3CacheSize()) {
    Eigen::setCpuCacheSizes(32 * 1024, 1024 * 1024, 32 * 1024 * 1024);
  }
  ~FixedProductBlocking() { Eigen::setCpuCacheSizes(l1_, l2_, l3_); }
  FixedProductBlocking(const FixedProductBlocking&) = delete;
  FixedProductBlocking& operator=(const FixedProductBlocking&) = delete;

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> lock_;
  std::ptrdiff_t l1_, l2_, l3_;
};

Eigen::MatrixXd orthonormalize(const Eigen::MatrixXd& m) {
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(m);
  return qr.householderQ() * Eigen::MatrixXd::Identity(m.rows(), m.cols());
}

}  // namespace

PrincipalComponents principal_components(Eigen::MatrixXd& bodies, int k, std::uint64_t seed) {
  const auto n = static_cast<int>(bodies.rows());
  const Eigen::Index dim = bodies.cols();
  if (k < 1 || n < k + 1) throw Error(ErrorKind::Format, "PCA needs at least k + 1 bodies", "subjects");
  // PCA by a randomized range finder with power iterations (Halko, Martinsson & Tropp 2011):
  // exact to double precision for the leading components of such a low-rank population, and
  // far cheaper than the n×n Gram matrix.
  const FixedProductBlocking same_sums_on_every_machine;
  PrincipalComponents out;
  out.mean = bodies.colwise().mean();
  bodies.rowwise() -= out.mean;
  const int l = std::min(n, k + 12);
  NormalGenerator normal(seed);
  Eigen::MatrixXd omega(n, l);
  for (Eigen::Index c = 0; c < omega.cols(); ++c)
    for (Eigen::Index r = 0; r < omega.rows(); ++r) omega(r, c) = normal.normal();
  Eigen::MatrixXd q = orthonormalize(bodies.transpose() * omega);  // dim × l
  for (int it = 0; it < 4; ++it) q = orthonormalize(bodies.transpose() * orthonormalize(bodies * q));
  const Eigen::MatrixXd b = bodies * q;  // n × l
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(b, Eigen::ComputeThinV);
  const Eigen::MatrixXd directions = q * svd.matrixV();  // dim × l, unit columns
  const double total_variance = bodies.squaredNorm() / (n - 1);
  out.directions.resize(dim, k);
  for (int c = 0; c < k; ++c) {
    const double sd = svd.singularValues()(c) / std::sqrt(n - 1.0);
    Eigen::VectorXd dir = directions.col(c);
    // Fix the sign so builds are reproducible and "+β" reads as "more": the largest entry positive.
    Eigen::Index arg = 0;
    dir.cwiseAbs().maxCoeff(&arg);
    if (dir(arg) < 0) dir = -dir;
    out.directions.col(c) = dir * sd;  // β ~ N(0, I)
    out.explained.push_back(sd * sd / total_variance);
  }
  return out;
}

WeightCalibration calibrate_weight_from_volume(const std::vector<double>& volumes, const std::vector<double>& weights,
                                               Sex sex) {
  const auto n = static_cast<int>(volumes.size());
  if (n < 2 || weights.size() != volumes.size())
    throw Error(ErrorKind::Format, "weight calibration needs at least 2 (volume, weight) pairs", "subjects");
  Eigen::MatrixXd x(n, 2);
  Eigen::VectorXd y(n);
  for (int i = 0; i < n; ++i) {
    x(i, 0) = volumes[static_cast<size_t>(i)];
    x(i, 1) = 1.0;
    y(i) = weights[static_cast<size_t>(i)];
  }
  const Eigen::Vector2d ab = x.colPivHouseholderQr().solve(y);
  WeightCalibration out;
  out.fitted = {ab(0), ab(1)};
  const WeightFromVolume paper = WeightFromVolume::paper(sex);
  for (int i = 0; i < n; ++i) {
    out.mae_fitted_kg += std::abs(ab(0) * x(i, 0) + ab(1) - y(i)) / n;
    const double p = paper.a * x(i, 0) + paper.b - y(i);
    out.mae_paper_kg += std::abs(p) / n;
    out.bias_paper_kg += p / n;
  }
  return out;
}

RealToVirtualFit fit_real_to_virtual(const BodyModel& provisional, const Eigen::MatrixXd& bodies,
                                     const Eigen::RowVectorXd& mean, const std::vector<const AnsurSubject*>& subjects) {
  const auto n = static_cast<int>(subjects.size());
  const Eigen::Index vertex_count = provisional.vertex_count();
  RealToVirtual maps;
  std::ostringstream fits;
  for (const auto& [name, real_of] : std::vector<std::pair<std::string, std::function<double(const AnsurSubject&)>>>{
           {"span", [](const AnsurSubject& s) { return s.values.at("span"); }},
           {"crotch_height", [](const AnsurSubject& s) { return s.values.at("crotchheight"); }},
           {"hip_breadth", [](const AnsurSubject& s) { return s.values.at("hipbreadth"); }},
           {"arm_length", [](const AnsurSubject& s) {
              return s.values.at("acromionradialelength") + s.values.at("radialestylionlength");
            }}}) {
    const MeasurementDefinition* def = provisional.find_measurement(name);
    if (!def) continue;
    Eigen::MatrixXd xr(n, 2);
    Eigen::VectorXd yv(n);
    for (int i = 0; i < n; ++i) {
      const Eigen::RowVectorXd body = bodies.row(i) + mean;
      const Vertices v = Eigen::Map<const Vertices>(body.data(), vertex_count, 3);
      xr(i, 0) = real_of(*subjects[static_cast<size_t>(i)]);
      xr(i, 1) = 1.0;
      yv(i) = measure(provisional, *def, v);
    }
    const Eigen::Vector2d fit = xr.colPivHouseholderQr().solve(yv);
    const double rmse = std::sqrt((xr * fit - yv).squaredNorm() / n);
    const double mean_gap = (yv - xr.col(0)).cwiseAbs().mean();
    // Rounded to what a fit over thousands of bodies can say (an identity comes out as 1 and 0,
    // not 1e-13 of float noise).
    auto round_to = [](double v, double step) { return std::round(v / step) * step + 0.0; };
    fits << name << ": virtual = " << round_to(fit(0), 1e-6) << " * real + " << round_to(fit(1) * 100, 1e-3) << " cm (rmse "
         << round_to(rmse * 100, 1e-3) << " cm, mean |virtual - real| " << round_to(mean_gap * 100, 1e-3) << " cm); ";
    if (mean_gap < 0.002) continue;  // reproduced by construction: identity
    LinearMap lm;
    lm.slope = fit(0);
    lm.offset = fit(1);
    lm.pairs = n;
    lm.rmse = rmse;
    maps.set(name, lm);
  }
  return {maps.to_json(), fits.str()};
}

namespace {
// Whom the model's "plausible" refers to, in words: the subjects' sex, count, and
// ranges of age, BMI and stature.
std::string describe_population(const std::vector<const AnsurSubject*>& subjects, Sex sex) {
  double age_lo = INFINITY, age_hi = -INFINITY, bmi_lo = INFINITY, bmi_hi = -INFINITY, h_lo = INFINITY, h_hi = -INFINITY;
  for (const AnsurSubject* s : subjects) {
    if (std::isfinite(s->age_years)) { age_lo = std::min(age_lo, s->age_years); age_hi = std::max(age_hi, s->age_years); }
    const double h = s->values.at("stature"), bmi = s->values.at("weightkg") / (h * h);
    bmi_lo = std::min(bmi_lo, bmi);
    bmi_hi = std::max(bmi_hi, bmi);
    h_lo = std::min(h_lo, h);
    h_hi = std::max(h_hi, h);
  }
  const char* who = sex == Sex::Female ? "women" : sex == Sex::Male ? "men" : "women and men";
  std::ostringstream d;
  d << "ANSUR II, US Army personnel measured in 2010-2012: " << subjects.size() << " " << who;
  if (std::isfinite(age_lo)) d << " aged " << std::lround(age_lo) << "-" << std::lround(age_hi);
  d << ", BMI " << std::lround(bmi_lo) << "-" << std::lround(bmi_hi) << ", stature " << std::lround(h_lo * 100) << "-"
    << std::lround(h_hi * 100) << " cm";
  return d.str();
}
}  // namespace

GeneratedPopulation generate_population(const std::vector<AnsurSubject>& all, Sex sex, int threads,
                                        const std::function<void(int, int)>& progress) {
  GeneratedPopulation pop;
  for (const auto& s : all)
    if (sex == Sex::Neutral || s.sex == sex) pop.subjects.push_back(&s);
  const int n = static_cast<int>(pop.subjects.size());
  const Topology& topo = topology();
  const Eigen::Index dim = 3 * static_cast<Eigen::Index>(topo.vertex_count);
  pop.bodies.resize(n, dim);
  pop.volumes.assign(static_cast<size_t>(n), 0.0);
  const std::vector<std::string> errors = caliper::detail::parallel_for(
      n, threads,
      [&](int i) {
        const AnsurSubject& subject = *pop.subjects[static_cast<size_t>(i)];
        Dimensions dims;
        for (const auto& col : input_columns()) {
          auto it = subject.values.find(col);
          if (it != subject.values.end()) dims[col] = it->second;
        }
        const Vertices v = generate(complete_dimensions(dims, subject.sex), subject.sex);
        pop.bodies.row(i) = Eigen::Map<const Eigen::RowVectorXd>(v.data(), dim);
        pop.volumes[static_cast<size_t>(i)] = signed_volume(v, topo.faces);
      },
      progress);
  for (int i = 0; i < n; ++i)
    if (!errors[static_cast<size_t>(i)].empty())
      throw Error(ErrorKind::Format, "subject " + pop.subjects[static_cast<size_t>(i)]->id + ": " + errors[static_cast<size_t>(i)],
                  "subjects");
  return pop;
}

BodyModel build_mannequin_model(const std::vector<AnsurSubject>& all, Sex sex, const PopulationOptions& options,
                                PopulationReport* report) {
  const int k = options.components;
  if (k < 1 || k > kMaxComponents)
    throw Error(ErrorKind::OutOfRange, "components must be in [1, " + std::to_string(kMaxComponents) + "]", "components");
  int n = 0;
  for (const auto& s : all) n += sex == Sex::Neutral || s.sex == sex;
  if (n < k + 1)
    throw Error(ErrorKind::Format, "need at least " + std::to_string(k + 1) + " " + to_string(sex) +
                                       " subjects, got " + std::to_string(n), "subjects");
  GeneratedPopulation pop = generate_population(all, sex, options.threads, options.progress);
  return model_from_population(pop, sex, options, report);
}

namespace {
// A model's data with the built-in body's topology, rig, landmarks and measurements around
// `body`; the caller adds the name, shape directions and UVs.
BodyModelData topology_model_data(const Vertices& body, Sex sex) {
  const Topology& topo = topology();
  BodyModelData d;
  d.sex = sex;
  d.template_vertices = body;
  d.faces = topo.faces;
  d.joint_regressor = topo.joint_regressor;
  d.joint_names = rig_joint_names();
  d.parents = rig_parents();
  d.skin_weights = topo.skin_weights;
  d.landmarks = topo.landmarks;
  d.measurements = measurement_definitions();
  return d;
}
}  // namespace

BodyModel model_from_population(GeneratedPopulation& pop, Sex sex, const PopulationOptions& options,
                                PopulationReport* report) {
  const int k = options.components;
  const int n = static_cast<int>(pop.subjects.size());
  if (k < 1 || k > kMaxComponents)
    throw Error(ErrorKind::OutOfRange, "components must be in [1, " + std::to_string(kMaxComponents) + "]", "components");
  if (n < k + 1)
    throw Error(ErrorKind::Format, "need at least " + std::to_string(k + 1) + " subjects, got " + std::to_string(n), "subjects");
  const Topology& topo = topology();
  Eigen::MatrixXd& bodies = pop.bodies;
  const std::vector<double>& volumes = pop.volumes;
  const std::vector<const AnsurSubject*>& subjects = pop.subjects;

  const PrincipalComponents pca = principal_components(bodies, k, options.seed);
  const Eigen::RowVectorXd& mean = pca.mean;

  BodyModelData d = topology_model_data(Eigen::Map<const Vertices>(mean.data(), topo.vertex_count, 3), sex);
  d.name = std::string("mannequin-") + to_string(sex);
  d.shape_directions = pca.directions;
  const std::vector<double>& explained = pca.explained;
  {
    UvLayout uv = uv_layout(d.template_vertices);  // unwrapped from this model's mean body
    d.uv_coordinates = std::move(uv.coordinates);
    d.uv_faces = std::move(uv.faces);
  }

  // weight = a·volume + b on the subjects' real weights (paper §3.4.2, here on ANSUR II).
  std::vector<double> weights(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) weights[static_cast<size_t>(i)] = subjects[static_cast<size_t>(i)]->values.at("weightkg");
  const WeightCalibration cal = calibrate_weight_from_volume(volumes, weights, sex);
  d.weight_from_volume = cal.fitted;
  const Eigen::Vector2d ab(cal.fitted.a, cal.fitted.b);
  const double mae_fit = cal.mae_fitted_kg, mae_paper = cal.mae_paper_kg, bias_paper = cal.bias_paper_kg;
  double total_explained = 0;
  for (double e : explained) total_explained += e;

  std::ostringstream ev;
  for (size_t i = 0; i < explained.size(); ++i) ev << (i ? "," : "") << std::round(explained[i] * 1e6) / 1e6;
  d.metadata = {{"source", "ANSUR II development subset (public domain), Gordon et al. 2014"},
                {"licence", "Caliper's own model: derived by Caliper's code from public-domain measurements"},
                {"generator", "caliper mannequin (procedural body)"},
                {"subjects", std::to_string(n)},
                {"explained_variance", ev.str()},
                {"weight_fit", "weight_kg = " + std::to_string(ab(0)) + " * volume_m3 + " + std::to_string(ab(1))},
                {"weight_mae_fitted_kg", std::to_string(mae_fit)},
                {"weight_mae_paper_kg", std::to_string(mae_paper)},
                {"rebuild", "caliper model build mannequin --ansur ../shared/data/ansur2 --sex " + std::string(to_string(sex))},
                {"population", describe_population(subjects, sex)}};
  // Real → virtual maps (paper §3.3) for the Virtual Caliper inputs whose virtual measurement on
  // the generated body differs systematically from the real one (e.g. arm length: ANSUR measures
  // it with the arm hanging, the avatar stands in a T-pose). Fitted on these same bodies.
  {
    const RealToVirtualFit r2v = fit_real_to_virtual(BodyModel{BodyModelData(d)}, bodies, mean, subjects);
    d.metadata["real_to_virtual"] = r2v.maps_json;
    d.metadata["real_to_virtual_fits"] = r2v.fits;
  }
  if (report) {
    report->subjects = n;
    report->explained_variance = explained;
    report->total_explained = total_explained;
    report->fitted = d.weight_from_volume;
    report->weight_mae_fitted_kg = mae_fit;
    report->weight_mae_paper_kg = mae_paper;
    report->weight_bias_paper_kg = bias_paper;
  }
  return BodyModel(std::move(d));
}

}  // namespace caliper::mannequin

namespace caliper::mannequin {

std::vector<RegionCreaseSurvey> survey_creases(const GeneratedPopulation& pop, int threads) {
  const Topology& topo = topology();
  const std::vector<std::string>& joints = rig_joint_names();
  const std::vector<BodyRegion> regions = vertex_regions(topo.skin_weights, joints);
  const int n = static_cast<int>(pop.bodies.rows());
  std::vector<std::vector<CreaseRegionSummary>> per_body(static_cast<size_t>(n));
  caliper::detail::parallel_for(n, threads, [&](int i) {
    const Eigen::RowVectorXd flat = pop.bodies.row(i);  // bodies is column-major: copy the row out first
    const Vertices v = Eigen::Map<const Vertices>(flat.data(), topo.vertex_count, 3);
    per_body[static_cast<size_t>(i)] = crease_report(v, topo.faces, regions);
  });
  std::map<BodyRegion, RegionCreaseSurvey> survey;
  std::map<BodyRegion, std::vector<double>> body_maxima;
  for (int i = 0; i < n; ++i)
    for (const CreaseRegionSummary& s : per_body[static_cast<size_t>(i)]) {
      RegionCreaseSurvey& r = survey[s.region];
      r.region = s.region;
      body_maxima[s.region].push_back(s.max_degrees);
      r.max_p99_degrees = std::max(r.max_p99_degrees, s.p99_degrees);
      if (s.max_degrees > r.max_degrees)
        r.max_degrees = s.max_degrees, r.worst_edge = s.worst, r.worst_subject = pop.subjects[static_cast<size_t>(i)]->id;
    }
  std::vector<RegionCreaseSurvey> out;
  for (auto& [region, r] : survey) {
    auto& maxima = body_maxima[region];
    std::nth_element(maxima.begin(), maxima.begin() + static_cast<std::ptrdiff_t>(maxima.size() / 2), maxima.end());
    r.median_body_max_degrees = maxima[maxima.size() / 2];
    out.push_back(r);
  }
  return out;
}

BodyModel measuring_model(const Vertices& body, Sex sex) {
  BodyModelData d = topology_model_data(body, sex);
  d.name = std::string("mannequin-") + to_string(sex) + "-measuring";
  d.shape_directions = Eigen::MatrixXd::Zero(3 * body.rows(), 1);
  return BodyModel(std::move(d));
}

std::vector<TargetFidelity> survey_fidelity(const GeneratedPopulation& pop, int threads) {
  std::vector<TargetFidelity> rows;
  for (const FidelityTarget& t : fidelity_targets()) {
    TargetFidelity row;
    row.target = t;
    rows.push_back(row);
  }
  const std::vector<MeasurementDefinition> all = measurement_definitions();
  std::vector<MeasurementDefinition> definitions;
  for (const TargetFidelity& row : rows) {
    auto def = std::find_if(all.begin(), all.end(), [&](const auto& d) { return d.name == row.target.measurement; });
    if (def == all.end()) throw Error(ErrorKind::Format, "no measurement " + row.target.measurement, "measurement");
    definitions.push_back(*def);
  }
  const int n = static_cast<int>(pop.bodies.rows());
  const Eigen::Index vertex_count = topology().vertex_count;
  // errors(i, r): body i's measured − ANSUR value of row r, metres.
  Eigen::MatrixXd errors(n, static_cast<Eigen::Index>(rows.size()));
  caliper::detail::parallel_for(n, threads, [&](int i) {
    const AnsurSubject& subject = *pop.subjects[static_cast<size_t>(i)];
    const Eigen::RowVectorXd flat = pop.bodies.row(i);  // bodies is column-major: copy the row out first
    const Vertices v = Eigen::Map<const Vertices>(flat.data(), vertex_count, 3);
    const BodyModel model = measuring_model(v, subject.sex);
    for (size_t r = 0; r < rows.size(); ++r)
      errors(i, static_cast<Eigen::Index>(r)) = measure(model, definitions[r], v) - subject.values.at(rows[r].target.ansur_column);
  });
  for (size_t r = 0; r < rows.size(); ++r) {
    TargetFidelity& row = rows[r];
    row.bodies = n;
    for (int i = 0; i < n; ++i) {
      const double error = errors(i, static_cast<Eigen::Index>(r));
      const double want = pop.subjects[static_cast<size_t>(i)]->values.at(row.target.ansur_column);
      row.mean_error_m += error / n;
      if (std::abs(error) > row.max_abs_error_m)
        row.max_abs_error_m = std::abs(error), row.worst_subject = pop.subjects[static_cast<size_t>(i)]->id;
      row.max_abs_error_fraction = std::max(row.max_abs_error_fraction, std::abs(error) / want);
      row.out_of_tolerance += row.target.circumference ? std::abs(error) > 0.01 * want : std::abs(error) > 0.003;
    }
  }
  return rows;
}

}  // namespace caliper::mannequin
