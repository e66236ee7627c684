#include "caliper/avatar_report.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <nlohmann/json.hpp>

#include "caliper/export/fbx.h"
#include "caliper/export/gltf.h"
#include "caliper/vocabulary/catalogue.h"
#include "export/export_common.h"

namespace caliper {

namespace {
// Dividing by the inverse step gives the double nearest the decimal, so JSON shows "57.044", not
// "57.044000000000004".
double round_to(double v, double step) { return std::round(v / step) / std::round(1.0 / step); }
}  // namespace

std::string avatar_report_json(const BodyModel& model, const Avatar& avatar, int indent) {
  using nlohmann::ordered_json;
  ordered_json j;
  j["model"] = model.name();
  j["sex"] = to_string(model.sex());
  j["regressor"] = avatar.regressor;
  j["inputs"] = avatar.inputs;
  j["beta"] = ordered_json::array();
  for (Eigen::Index i = 0; i < avatar.beta.size(); ++i) j["beta"].push_back(round_to(avatar.beta(i), 1e-6));
  ordered_json per = ordered_json::array();
  for (auto v : avatar.plausibility.per_value) per.push_back(to_string(v));
  const Plausibility& p = avatar.plausibility;
  j["plausibility"] = {{"verdict", to_string(p.overall)},
                       {"rarity", p.rarity},
                       {"tail_probability", p.tail_probability},
                       {"population", p.population},
                       {"drivers", p.drivers},
                       {"per_value", per},
                       {"mahalanobis_sq", round_to(p.mahalanobis_sq, 1e-4)},
                       {"explanation", p.explanation},
                       {"bands", "overall: share of the population further from its average (chi-square of |beta|^2) "
                                 "below 1 % unusual, below 0.1 % implausible; per value: |beta| <= 2 plausible, 2-3 "
                                 "unusual, > 3 implausible"}};
  if (avatar.noise_widened > 1) j["plausibility"]["outside_population_noise_widened"] = round_to(avatar.noise_widened, 1e-3);
  ordered_json ms = ordered_json::object();
  bool any_rest_pose = false;
  for (const auto& [name, rest_pose] : avatar.achieved) {
    const MeasurementInfo* info = find_measurement_info(name);
    const bool kg = info && info->unit == Unit::Kilogram;
    const std::string suffix = kg ? "_kg" : "_cm";
    const double scale = kg ? 1.0 : 100.0;
    // Every value is what a person measures (arm length with the arm hanging), so achieved and
    // difference compare like with like; a mapped measurement also gives the avatar's own value
    // in its T-pose rest pose and the rest-pose value it was built for (paper §3.3).
    const double achieved = as_measured(avatar, name, rest_pose);
    ordered_json m = ordered_json::object();
    auto req = avatar.requested.find(name);
    if (req != avatar.requested.end()) m["requested" + suffix] = round_to(req->second * scale, 1e-3);
    m["achieved" + suffix] = round_to(achieved * scale, 1e-3);
    if (req != avatar.requested.end()) m["difference" + suffix] = round_to((achieved - req->second) * scale, 1e-3);
    // Posterior SD of the avatar's value ("map" only): achieved ± uncertainty.
    if (auto u = avatar.uncertainty.find(name); u != avatar.uncertainty.end())
      m["uncertainty" + suffix] = round_to(sd_as_measured(avatar, name, u->second) * scale, 1e-3);
    if (measured_differs_from_rest_pose(avatar, name)) {
      any_rest_pose = true;
      m["rest_pose" + suffix] = round_to(rest_pose * scale, 1e-3);
      if (auto t = avatar.targets.find(name); t != avatar.targets.end())
        m["rest_pose_target" + suffix] = round_to(t->second * scale, 1e-3);
    }
    ms[name] = m;
  }
  // Requested values the model cannot measure are still reported, so nothing the user gave vanishes.
  for (const auto& [name, requested] : avatar.requested)
    if (!avatar.achieved.count(name)) {
      const MeasurementInfo* info = find_measurement_info(name);
      const bool kg = info && info->unit == Unit::Kilogram;
      ms[name] = {{kg ? "requested_kg" : "requested_cm", round_to(requested * (kg ? 1 : 100), 1e-3)}, {"achieved_cm", nullptr}};
    }
  j["measurements"] = ms;
  if (any_rest_pose)
    j["rest_pose_note"] = "requested, achieved and difference are as a person measures them; rest_pose is the avatar's own "
                          "value in its T-pose rest pose, through the real-to-virtual map (paper section 3.3)";
  j["warnings"] = avatar.warnings;
  if (avatar.beta_covariance.size() > 0) {
    // The estimator's side of the uncertainty: noise assumed per input, how each input fitted
    // (z: its standardised residual against the others), β's SDs and the vertex SDs' summary.
    ordered_json u;
    u["noise"] = avatar.noise;
    ordered_json inputs = ordered_json::object();
    for (const auto& [name, fit] : avatar.input_fits) {
      const MeasurementInfo* info = find_measurement_info(name);
      const bool kg = info && info->unit == Unit::Kilogram;
      const std::string suffix = kg ? "_kg" : "_cm";
      const double scale = kg ? 1.0 : 100.0;
      // As a person measures it, like the measurements above (z is the same in either terms).
      inputs[name] = {{"noise_sd" + suffix, round_to(sd_as_measured(avatar, name, fit.noise_sd) * scale, 1e-4)},
                      {"effective_sd" + suffix, round_to(sd_as_measured(avatar, name, fit.effective_sd) * scale, 1e-4)},
                      {"expected" + suffix, round_to(as_measured(avatar, name, fit.expected) * scale, 1e-3)},
                      {"expected_sd" + suffix, round_to(sd_as_measured(avatar, name, fit.expected_sd) * scale, 1e-3)},
                      {"z", round_to(fit.z, 1e-3)}};
    }
    u["inputs"] = inputs;
    u["beta_sd"] = ordered_json::array();
    for (Eigen::Index i = 0; i < avatar.beta_covariance.rows(); ++i)
      u["beta_sd"].push_back(round_to(std::sqrt(std::max(0.0, avatar.beta_covariance(i, i))), 1e-6));
    if (avatar.vertex_sd.size() > 0)
      u["vertex_sd_cm"] = {{"mean", round_to(avatar.vertex_sd.mean() * 100, 1e-3)},
                           {"max", round_to(avatar.vertex_sd.maxCoeff() * 100, 1e-3)}};
    j["uncertainty"] = u;
  }
  j["vertex_count"] = model.vertex_count();
  j["joint_count"] = model.joint_count();
  return j.dump(indent) + "\n";
}

Provenance avatar_provenance(const BodyModel& model, const Avatar& avatar) {
  Provenance p = model_provenance(model);
  p.regressor = avatar.regressor;
  p.measurements = avatar.requested;
  return p;
}

namespace {
std::string lower(std::string text) {
  for (auto& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}
constexpr AvatarFormat kAvatarFormats[] = {AvatarFormat::Glb, AvatarFormat::Vrm, AvatarFormat::Fbx, AvatarFormat::Obj};
}  // namespace

const char* to_string(AvatarFormat format) {
  switch (format) {
    case AvatarFormat::Glb: return "glb";
    case AvatarFormat::Vrm: return "vrm";
    case AvatarFormat::Fbx: return "fbx";
    case AvatarFormat::Obj: return "obj";
  }
  return "?";
}

std::optional<AvatarFormat> avatar_format_named(const std::string& name) {
  for (AvatarFormat f : kAvatarFormats)
    if (lower(name) == to_string(f)) return f;
  return std::nullopt;
}

namespace {
std::optional<AvatarFormat> format_of_path(const std::string& path) {
  const std::size_t dot = path.rfind('.');
  if (dot == std::string::npos || path.find('/', dot) != std::string::npos) return std::nullopt;
  return avatar_format_named(path.substr(dot + 1));
}
}  // namespace

bool is_avatar_file_name(const std::string& path) { return format_of_path(path).has_value(); }

AvatarFormat avatar_file_format(const std::string& path, const std::string& field) {
  const std::optional<AvatarFormat> format = format_of_path(path);
  if (!format) throw Error(ErrorKind::InvalidArgument, field + " must end in .glb, .vrm, .fbx or .obj, got '" + path + "'", field);
  return *format;
}

bool avatar_format_carries_morphs(AvatarFormat format) { return format != AvatarFormat::Obj; }

void check_avatar_file_options(AvatarFormat format, const AvatarFileOptions& options, const std::string& field) {
  if (options.morphs && !avatar_format_carries_morphs(format)) {
    std::string carriers;
    for (AvatarFormat f : kAvatarFormats)
      if (avatar_format_carries_morphs(f)) carriers += (carriers.empty() ? "." : ", .") + std::string(to_string(f));
    throw Error(ErrorKind::InvalidArgument,
                std::string("morph targets: a .") + to_string(format) + " file cannot carry them (only " + carriers + " do)",
                field);
  }
}

std::string write_avatar(AvatarFormat format, const BodyModel& model, const Avatar& avatar, const AvatarFileOptions& options) {
  check_avatar_file_options(format, options, "morphs");
  if (format == AvatarFormat::Obj)
    return write_obj(avatar.rest_vertices, model.faces(), model.data().uv_coordinates, model.data().uv_faces,
                     "Caliper avatar, model " + model.name() + ", regressor " + avatar.regressor + ", metres, +Y up, facing +Z");
  GlbOptions glb;
  glb.skeleton = options.skeleton;
  glb.morphs = options.morphs;
  glb.provenance = avatar_provenance(model, avatar);
  if (format == AvatarFormat::Fbx) return write_fbx(model, avatar.rest_vertices, glb);
  // The map estimator's per-vertex SD travels with the mesh as the _UNCERTAINTY attribute.
  const Eigen::VectorXd& vsd = avatar.vertex_sd;
  glb.extra_vertex_scalar.assign(vsd.data(), vsd.data() + vsd.size());
  return format == AvatarFormat::Vrm ? write_vrm(model, avatar.rest_vertices, glb) : write_glb(model, avatar.rest_vertices, glb);
}

void save_avatar(const std::string& path, const BodyModel& model, const Avatar& avatar, const std::string& field,
                 const AvatarFileOptions& options) {
  const AvatarFormat format = avatar_file_format(path, field);
  check_avatar_file_options(format, options, field);
  export_detail::write_file(path, write_avatar(format, model, avatar, options));
}

}  // namespace caliper
