// The MakeHuman body model: sliders fitted per ANSUR II subject, PCA of the fitted
// bodies (shared with the built-in body, mannequin/population.h), joint regressor, volume →
// weight (paper §3.4.2 redone on ANSUR). The fit is a damped Gauss–Newton over the sliders with
// a Broyden-updated Jacobian (Broyden 1965): one finite-difference Jacobian per gender, then one
// body per step, which is what keeps a population build within two minutes on two cores.
#include "caliper/makehuman/builder.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <mutex>
#include <sstream>

#include "caliper/errors.h"
#include "caliper/makehuman/landmarks.h"
#include "caliper/mannequin/population.h"
#include "caliper/measure/geometry.h"
#include "caliper/measure/measure.h"
#include "parallel.h"

namespace caliper::makehuman {

namespace {

double gender_of(Sex sex) { return sex == Sex::Female ? 0.0 : sex == Sex::Male ? 1.0 : 0.5; }

// Race weights from ANSUR's DODRace (1 White, 2 Black, 3 Hispanic, 4 Asian, 5 Native American,
// 6 Pacific Islander, 8 Other): MakeHuman has three race targets; mixed or other groups get a
// blend. A modelling choice of ours, documented in docs/makehuman.md.
void set_race(MacroSliders& m, double dodrace) {
  const int r = static_cast<int>(std::lround(dodrace));
  m.african = m.asian = m.caucasian = 1.0 / 3;
  if (r == 1) m.african = 0, m.asian = 0, m.caucasian = 1;
  if (r == 2) m.african = 1, m.asian = 0, m.caucasian = 0;
  if (r == 3) m.african = 0.2, m.asian = 0.2, m.caucasian = 0.6;
  if (r == 4) m.african = 0, m.asian = 1, m.caucasian = 0;
}

struct Param {
  std::string name;  // macro slider or modifier name
  bool macro = false;
  double lo = 0, hi = 1, prior = 0.5, sigma = 0.5;
};

class Fitter {
 public:
  Fitter(const Assets& assets, const BodyModel& reference) : assets_(assets), ref_(reference) {
    // A weak prior (σ = 1 slider range) only settles what the measurements leave free.
    for (const char* m : {"muscle", "weight", "height", "proportions", "cupsize"}) params_.push_back({m, true, 0, 1, 0.5, 1.0});
    for (const auto& name : modifier_names(assets)) params_.push_back({name, false, -1, 1, 0, 1.0});
    for (const auto& t : fit_targets())
      if (ref_.find_measurement(t.measurement)) {
        targets_.push_back(t);
        names_.push_back(t.measurement);
      }
  }
  int param_count() const { return static_cast<int>(params_.size()); }
  int target_count() const { return static_cast<int>(targets_.size()); }
  const std::vector<FitTarget>& targets() const { return targets_; }

  Shape shape(const MacroSliders& base, const Eigen::VectorXd& p) const {
    Shape s;
    s.macro = base;
    for (int i = 0; i < param_count(); ++i) {
      const Param& q = params_[static_cast<size_t>(i)];
      if (!q.macro) s.modifiers[q.name] = p(i);
      else if (q.name == "muscle") s.macro.muscle = p(i);
      else if (q.name == "weight") s.macro.weight = p(i);
      else if (q.name == "height") s.macro.height = p(i);
      else if (q.name == "proportions") s.macro.proportions = p(i);
      else if (q.name == "cupsize") s.macro.cupsize = p(i);
    }
    return s;
  }
  Eigen::VectorXd prior() const {
    Eigen::VectorXd p(param_count());
    for (int i = 0; i < param_count(); ++i) p(i) = params_[static_cast<size_t>(i)].prior;
    return p;
  }
  Eigen::VectorXd clamp(Eigen::VectorXd p) const {
    for (int i = 0; i < param_count(); ++i) p(i) = std::clamp(p(i), params_[static_cast<size_t>(i)].lo, params_[static_cast<size_t>(i)].hi);
    return p;
  }
  // Measurements of the fit targets (SI), in targets() order.
  Eigen::VectorXd measure(const MacroSliders& base, const Eigen::VectorXd& p, PosedBody* body = nullptr) const {
    PosedBody posed = t_pose(assets_, morph(assets_, shape(base, p)));
    const auto values = measure_some(ref_, names_, posed.body);
    Eigen::VectorXd m(target_count());
    for (int i = 0; i < target_count(); ++i) m(i) = values.at(names_[static_cast<size_t>(i)]);
    if (body) *body = std::move(posed);
    return m;
  }
  // Central-difference Jacobian of the measurements at the prior, for one base (gender).
  Eigen::MatrixXd jacobian(const MacroSliders& base) const {
    const Eigen::VectorXd p0 = prior();
    Eigen::MatrixXd j(target_count(), param_count());
    const double h = 0.1;
    for (int c = 0; c < param_count(); ++c) {
      Eigen::VectorXd a = p0, b = p0;
      a(c) = std::min(p0(c) + h, params_[static_cast<size_t>(c)].hi);
      b(c) = std::max(p0(c) - h, params_[static_cast<size_t>(c)].lo);
      j.col(c) = (measure(base, a) - measure(base, b)) / (a(c) - b(c));
    }
    return j;
  }

  struct Result {
    Eigen::VectorXd p;
    Eigen::VectorXd achieved;
    PosedBody body;
    int evaluations = 0;
  };
  // Damped Gauss–Newton on Σ ((m − t)/σ)² + Σ ((p − p0)/σp)², p within bounds.
  Result fit(const MacroSliders& base, const Eigen::VectorXd& target, const Eigen::VectorXd& sigma_inv,
             Eigen::MatrixXd j, int iterations) const {
    const int np = param_count();
    const Eigen::VectorXd p0 = prior();
    Eigen::VectorXd prior_w(np);
    for (int i = 0; i < np; ++i) prior_w(i) = 1.0 / params_[static_cast<size_t>(i)].sigma;
    Result r;
    r.p = p0;
    r.achieved = measure(base, r.p, &r.body);
    r.evaluations = 1;
    auto cost = [&](const Eigen::VectorXd& m, const Eigen::VectorXd& p) {
      return (sigma_inv.asDiagonal() * (m - target)).squaredNorm() + (prior_w.asDiagonal() * (p - p0)).squaredNorm();
    };
    double best = cost(r.achieved, r.p);
    // Trust region on the largest slider change: the measurements are only piecewise linear in
    // the sliders (kinks at 0.5 and at 0), so long steps from a borrowed Jacobian overshoot.
    double radius = 0.4;
    for (int it = 0; it < iterations; ++it) {
      const Eigen::MatrixXd a = sigma_inv.asDiagonal() * j;
      const Eigen::VectorXd res = sigma_inv.asDiagonal() * (r.achieved - target);
      Eigen::MatrixXd h = a.transpose() * a;
      h.diagonal() += prior_w.cwiseAbs2();
      const Eigen::VectorXd g = a.transpose() * res + prior_w.cwiseAbs2().asDiagonal() * (r.p - p0);
      Eigen::VectorXd delta = -h.ldlt().solve(g);
      const double longest = delta.cwiseAbs().maxCoeff();
      if (longest > radius) delta *= radius / longest;
      const Eigen::VectorXd p_new = clamp(r.p + delta);
      const Eigen::VectorXd step = p_new - r.p;
      if (step.cwiseAbs().maxCoeff() < 1e-3) break;
      PosedBody body;
      const Eigen::VectorXd m_new = measure(base, p_new, &body);
      ++r.evaluations;
      // Broyden's rank-one update: the Jacobian learns this subject's curvature and kinks.
      j += ((m_new - r.achieved) - j * step) * step.transpose() / step.squaredNorm();
      const double c = cost(m_new, p_new);
      if (c < best) {
        best = c;
        r.p = p_new;
        r.achieved = m_new;
        r.body = std::move(body);
        radius = std::min(1.0, radius * 1.5);
      } else {
        radius /= 3;
      }
    }
    return r;
  }

 private:
  const Assets& assets_;
  const BodyModel& ref_;
  std::vector<Param> params_;
  std::vector<FitTarget> targets_;
  std::vector<std::string> names_;
};

Eigen::SparseMatrix<double, Eigen::RowMajor> nearest_vertex_regressor(const Vertices& body, const Eigen::MatrixX3d& joints) {
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index j = 0; j < joints.rows(); ++j) {
    Eigen::Index arg = 0;
    (body.rowwise() - joints.row(j)).rowwise().squaredNorm().minCoeff(&arg);
    t.emplace_back(static_cast<int>(j), static_cast<int>(arg), 1.0);
  }
  Eigen::SparseMatrix<double, Eigen::RowMajor> m(joints.rows(), body.rows());
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

}  // namespace

const std::vector<FitTarget>& fit_targets() {
  static const std::vector<FitTarget> targets = [] {
    // What MakeHuman's sliders can move and our landmarks measure as ANSUR does. Hand, foot and
    // head dimensions, the trunk's breadths and depths and the hip landmarks' heights have no
    // slider of their own; they are reported (docs/makehuman.md), not fitted.
    std::vector<FitTarget> t = {
        {"stature", {"stature"}, 0.005},
        {"weight", {"weightkg"}, 1.0},
        {"span", {"span"}, 0.01},
        {"crotch_height", {"crotchheight"}, 0.01},
        {"hip_breadth", {"hipbreadth"}, 0.01},
        {"upper_arm_length", {"acromionradialelength"}, 0.01},
        {"forearm_length", {"radialestylionlength"}, 0.01},
        {"biacromial_breadth", {"biacromialbreadth"}, 0.01},
        {"cervicale_height", {"cervicaleheight"}, 0.015},
        {"waist_height", {"waistheightomphalion"}, 0.015},
        {"knee_height", {"kneeheightmidpatella"}, 0.015},
        {"chest_circumference", {"chestcircumference"}, 0.02},
        {"waist_circumference", {"waistcircumference"}, 0.02},
        {"buttock_circumference", {"buttockcircumference"}, 0.02},
        {"neck_circumference", {"neckcircumference"}, 0.02},
        {"thigh_circumference", {"thighcircumference"}, 0.02},
        {"lower_thigh_circumference", {"lowerthighcircumference"}, 0.02},
        {"calf_circumference", {"calfcircumference"}, 0.02},
        {"ankle_circumference", {"anklecircumference"}, 0.02},
        {"wrist_circumference", {"wristcircumference"}, 0.02},
    };
    return t;
  }();
  return targets;
}

BodyModel reference_model(const Assets& assets, Sex sex) {
  Shape s;
  s.macro.gender = gender_of(sex);
  const PosedBody body = t_pose(assets, morph(assets, s));
  BodyModelData d;
  d.name = std::string("makehuman-reference-") + to_string(sex);
  d.sex = sex;
  d.template_vertices = body.body;
  d.faces = assets.mesh.body_faces;
  d.uv_coordinates = assets.mesh.body_uv;  // MakeHuman's own UV layout, when the assets have one
  d.uv_faces = assets.mesh.body_uv_faces;
  d.shape_directions = Eigen::MatrixXd::Zero(3 * static_cast<Eigen::Index>(kBodyVertexCount), 1);
  d.joint_regressor = nearest_vertex_regressor(body.body, body.joints);
  d.joint_names = smpl_joint_names();
  d.parents = smpl_parents();
  d.skin_weights = smpl_skin_weights(assets);
  d.landmarks = pick_landmarks(assets);
  d.measurements = measurement_definitions();
  d.weight_from_volume = WeightFromVolume::paper(sex);
  return BodyModel(std::move(d));
}

BodyModel build_makehuman_model(const Assets& assets, const std::vector<AnsurSubject>& all, Sex sex,
                                const BuildOptions& options, BuildReport* report) {
  const int k = options.components;
  if (k < 1 || k > 64) throw Error(ErrorKind::OutOfRange, "components must be in [1, 64]", "components");
  if (options.max_subjects < 0) throw Error(ErrorKind::OutOfRange, "subjects must be ≥ 0 (0 = all)", "subjects");
  std::vector<const AnsurSubject*> pool;
  for (const auto& s : all)
    if ((sex == Sex::Neutral || s.sex == sex) && s.values.count("stature") && s.values.count("weightkg")) pool.push_back(&s);
  const int available = static_cast<int>(pool.size());
  std::vector<const AnsurSubject*> subjects;
  if (options.max_subjects > 0 && available > options.max_subjects) {
    // Evenly spaced through the file: deterministic and spread over the whole sample.
    for (int i = 0; i < options.max_subjects; ++i)
      subjects.push_back(pool[static_cast<size_t>(static_cast<long long>(i) * available / options.max_subjects)]);
  } else {
    subjects = pool;
  }
  const int n = static_cast<int>(subjects.size());
  if (n < k + 1)
    throw Error(ErrorKind::Format, "need at least " + std::to_string(k + 1) + " " + to_string(sex) + " subjects, got " +
                                       std::to_string(n), "subjects");

  const BodyModel reference = reference_model(assets, sex);
  const Fitter fitter(assets, reference);
  // One Jacobian per gender present (neutral models mix both).
  std::map<double, Eigen::MatrixXd> jacobians;
  for (const auto* s : subjects) jacobians[gender_of(s->sex)];
  for (auto& [g, j] : jacobians) {
    MacroSliders base;
    base.gender = g;
    j = fitter.jacobian(base);
  }

  const Eigen::Index dim = 3 * static_cast<Eigen::Index>(kBodyVertexCount);
  Eigen::MatrixXd bodies(n, dim);
  std::vector<Eigen::MatrixX3d> joints(static_cast<size_t>(n));
  std::vector<double> volumes(static_cast<size_t>(n));
  Eigen::MatrixXd residuals = Eigen::MatrixXd::Constant(n, fitter.target_count(), std::nan(""));
  const std::vector<std::string> errors = detail::parallel_for(
      n, options.threads,
      [&](int i) {
        const AnsurSubject& s = *subjects[static_cast<size_t>(i)];
        MacroSliders base;
        base.gender = gender_of(s.sex);
        if (auto it = s.values.find("age"); it != s.values.end()) base.age = age_slider(it->second * 1000);  // read as mm → m
        if (auto it = s.values.find("dodrace"); it != s.values.end()) set_race(base, it->second * 1000);
        Eigen::VectorXd target(fitter.target_count()), sigma_inv(fitter.target_count());
        for (int t = 0; t < fitter.target_count(); ++t) {
          const FitTarget& ft = fitter.targets()[static_cast<size_t>(t)];
          double v = 0;
          bool ok = true;
          for (const auto& c : ft.columns) {
            auto it = s.values.find(c);
            if (it == s.values.end()) ok = false;
            else v += it->second;
          }
          target(t) = ok ? v : 0;
          sigma_inv(t) = ok ? 1.0 / ft.sigma : 0;  // a missing column does not pull
        }
        auto r = fitter.fit(base, target, sigma_inv, jacobians.at(base.gender), options.iterations);
        bodies.row(i) = Eigen::Map<const Eigen::RowVectorXd>(r.body.body.data(), dim);
        volumes[static_cast<size_t>(i)] = signed_volume(r.body.body, assets.mesh.body_faces);
        joints[static_cast<size_t>(i)] = r.body.joints;
        for (int t = 0; t < fitter.target_count(); ++t)
          if (sigma_inv(t) > 0) residuals(i, t) = r.achieved(t) - target(t);
      },
      options.progress);
  std::vector<int> ok;
  std::vector<std::string> failed;
  for (int i = 0; i < n; ++i) {
    if (errors[static_cast<size_t>(i)].empty()) ok.push_back(i);
    else failed.push_back(subjects[static_cast<size_t>(i)]->id + ": " + errors[static_cast<size_t>(i)]);
  }
  const int m = static_cast<int>(ok.size());
  if (m < k + 1)
    throw Error(ErrorKind::Format, "only " + std::to_string(m) + " subjects could be fitted (" +
                                       (failed.empty() ? std::string("none failed") : failed.front()) + ")", "subjects");
  if (m < n) {
    Eigen::MatrixXd kept(m, dim);
    std::vector<Eigen::MatrixX3d> kj;
    std::vector<double> kv;
    Eigen::MatrixXd kr(m, residuals.cols());
    for (int r = 0; r < m; ++r) {
      kept.row(r) = bodies.row(ok[static_cast<size_t>(r)]);
      kj.push_back(joints[static_cast<size_t>(ok[static_cast<size_t>(r)])]);
      kv.push_back(volumes[static_cast<size_t>(ok[static_cast<size_t>(r)])]);
      kr.row(r) = residuals.row(ok[static_cast<size_t>(r)]);
    }
    bodies.swap(kept);
    joints.swap(kj);
    volumes.swap(kv);
    residuals.swap(kr);
  }
  std::vector<double> weights;
  for (int i : ok) weights.push_back(subjects[static_cast<size_t>(i)]->values.at("weightkg"));

  const mannequin::PrincipalComponents pca = mannequin::principal_components(bodies, k, options.seed);
  const mannequin::WeightCalibration cal = mannequin::calibrate_weight_from_volume(volumes, weights, sex);

  // Joint regressor over body vertices only (the rig's joints are means of helper cubes, which
  // the model does not carry): for each joint, the 24 body vertices nearest to it on the mean
  // body, weighted to reproduce the rig's joint on every fitted subject in the least-squares
  // sense (rows sum to 1, a small ridge towards equal weights keeps the weights tame).
  const Vertices mean_body = Eigen::Map<const Vertices>(pca.mean.data(), kBodyVertexCount, 3);
  Eigen::MatrixX3d mean_joints = Eigen::MatrixX3d::Zero(24, 3);
  for (const auto& j : joints) mean_joints += j / m;
  std::vector<Eigen::Triplet<double>> jr;
  double joint_sq = 0;
  const int kc = 24;
  for (int j = 0; j < 24; ++j) {
    const Eigen::VectorXd d2 = (mean_body.rowwise() - mean_joints.row(j)).rowwise().squaredNorm();
    std::vector<int> idx(static_cast<size_t>(kBodyVertexCount));
    for (int v = 0; v < kBodyVertexCount; ++v) idx[static_cast<size_t>(v)] = v;
    std::partial_sort(idx.begin(), idx.begin() + kc, idx.end(), [&](int a, int b) { return d2(a) < d2(b); });
    idx.resize(kc);
    Eigen::MatrixXd a(3 * m, kc);
    Eigen::VectorXd b(3 * m);
    for (int s = 0; s < m; ++s)
      for (int c = 0; c < 3; ++c) {
        for (int q = 0; q < kc; ++q) a(3 * s + c, q) = bodies(s, 3 * idx[static_cast<size_t>(q)] + c) + pca.mean(3 * idx[static_cast<size_t>(q)] + c);
        b(3 * s + c) = joints[static_cast<size_t>(s)](j, c);
      }
    // With Σw = 1, A·w − b = D·w where D holds each vertex's offset from the joint: the ridge is
    // scaled to those offsets (centimetres), not to absolute coordinates.
    const Eigen::MatrixXd offsets = a.colwise() - b;
    const Eigen::VectorXd w0 = Eigen::VectorXd::Constant(kc, 1.0 / kc);
    const double lambda = 1e-4 * (offsets.transpose() * offsets).trace() / kc;
    Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(kc + 1, kc + 1);
    kkt.topLeftCorner(kc, kc) = offsets.transpose() * offsets + lambda * Eigen::MatrixXd::Identity(kc, kc);
    kkt.block(0, kc, kc, 1).setOnes();
    kkt.block(kc, 0, 1, kc).setOnes();
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(kc + 1);
    rhs.head(kc) = lambda * w0;
    rhs(kc) = 1;
    const Eigen::VectorXd w = kkt.fullPivLu().solve(rhs).head(kc);
    joint_sq += (a * w - b).squaredNorm();
    for (int q = 0; q < kc; ++q) jr.emplace_back(j, idx[static_cast<size_t>(q)], w(q));
  }

  BodyModelData d;
  d.name = std::string("makehuman-") + to_string(sex);
  d.sex = sex;
  d.template_vertices = mean_body;
  d.faces = assets.mesh.body_faces;
  d.uv_coordinates = assets.mesh.body_uv;  // MakeHuman's own UV layout, when the assets have one
  d.uv_faces = assets.mesh.body_uv_faces;
  d.shape_directions = pca.directions;
  d.joint_regressor.resize(24, kBodyVertexCount);
  d.joint_regressor.setFromTriplets(jr.begin(), jr.end());
  d.joint_names = smpl_joint_names();
  d.parents = smpl_parents();
  d.skin_weights = reference.data().skin_weights;
  d.landmarks = reference.data().landmarks;
  d.measurements = reference.data().measurements;
  d.weight_from_volume = cal.fitted;

  double total_explained = 0;
  for (double e : pca.explained) total_explained += e;
  std::ostringstream ev, fit_text, problems;
  for (size_t i = 0; i < pca.explained.size(); ++i) ev << (i ? "," : "") << std::round(pca.explained[i] * 1e6) / 1e6;
  std::map<std::string, double> fit_mae;
  for (int t = 0; t < fitter.target_count(); ++t) {
    double s = 0;
    int c = 0;
    for (int i = 0; i < m; ++i)
      if (!std::isnan(residuals(i, t))) s += std::abs(residuals(i, t)), ++c;
    if (c) fit_mae[fitter.targets()[static_cast<size_t>(t)].measurement] = s / c;
  }
  for (const auto& [name, v] : fit_mae) {
    const bool kg = name == "weight";
    fit_text << name << " " << std::round((kg ? v : v * 100) * 100) / 100 << (kg ? " kg" : " cm") << "; ";
  }
  for (const auto& p : assets.problems) problems << p.name << ": " << p.reason << "; ";
  d.metadata = {{"source", "MakeHuman hm08 assets (CC0) fitted to the ANSUR II development subset (public domain)"},
                {"licence", "CC0 assets (MakeHuman / MPFB2) and public-domain measurements; built by Caliper's code"},
                {"generator", "caliper makehuman builder"},
                {"subjects", std::to_string(m)},
                {"subjects_available", std::to_string(available)},
                {"explained_variance", ev.str()},
                {"weight_fit", "weight_kg = " + std::to_string(cal.fitted.a) + " * volume_m3 + " + std::to_string(cal.fitted.b)},
                {"weight_mae_fitted_kg", std::to_string(cal.mae_fitted_kg)},
                {"weight_mae_paper_kg", std::to_string(cal.mae_paper_kg)},
                {"fit_mae", fit_text.str()},
                {"skipped_targets", problems.str()},
                {"rebuild", "caliper model build makehuman --assets DIR --ansur ../shared/data/ansur2 --sex " + std::string(to_string(sex)) +
                                " --components " + std::to_string(k) + " --subjects " + std::to_string(options.max_subjects)}};
  {
    // The same real → virtual maps as the built-in body (paper §3.3): e.g. ANSUR's arm lengths
    // are taken with the arm hanging, the avatar's in the T-pose.
    std::vector<const AnsurSubject*> used;
    for (int i : ok) used.push_back(subjects[static_cast<size_t>(i)]);
    const mannequin::RealToVirtualFit r2v = mannequin::fit_real_to_virtual(BodyModel{BodyModelData(d)}, bodies, pca.mean, used);
    d.metadata["real_to_virtual"] = r2v.maps_json;
    d.metadata["real_to_virtual_fits"] = r2v.fits;
  }
  if (report) {
    report->subjects_available = available;
    report->subjects = m;
    report->explained_variance = pca.explained;
    report->total_explained = total_explained;
    report->fitted = cal.fitted;
    report->weight_mae_fitted_kg = cal.mae_fitted_kg;
    report->weight_mae_paper_kg = cal.mae_paper_kg;
    report->weight_bias_paper_kg = cal.bias_paper_kg;
    report->fit_mae = fit_mae;
    report->joint_rms_m = std::sqrt(joint_sq / (24.0 * m));
    report->problems = assets.problems;
    report->failed_subjects = failed;
  }
  return BodyModel(std::move(d));
}

}  // namespace caliper::makehuman
