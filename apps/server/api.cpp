// The desktop tool's JSON API (docs/api.md): the paper's desktop application (§4.3, §5) as a
// handful of endpoints. A client of the library's public API only; measurements cross this edge
// in centimetres and kilograms, shapes and meshes come back as JSON and base64 arrays.
#include "api.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "caliper/caliper.h"
#include "capture_api.h"
#include "json_body.h"

namespace caliper::server {

namespace {

using nlohmann::ordered_json;
namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Small helpers.

std::string base64(const void* data, size_t size) {
  static const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const unsigned char*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const std::uint32_t v = (std::uint32_t(p[i]) << 16) | (std::uint32_t(p[i + 1]) << 8) | p[i + 2];
    out += alphabet[(v >> 18) & 63];
    out += alphabet[(v >> 12) & 63];
    out += alphabet[(v >> 6) & 63];
    out += alphabet[v & 63];
  }
  if (i < size) {
    std::uint32_t v = std::uint32_t(p[i]) << 16;
    if (i + 1 < size) v |= std::uint32_t(p[i + 1]) << 8;
    out += alphabet[(v >> 18) & 63];
    out += alphabet[(v >> 12) & 63];
    out += i + 1 < size ? alphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Thrown inside handlers for request problems that are not the library's (unknown route, wrong
// JSON type); turned into the same error body as a caliper::Error.
struct RequestError {
  int status;
  std::string message;
  std::string field;
  std::string kind;
  ordered_json details = nullptr;  // more for the client (e.g. suspect values), merged into "error"
};

[[noreturn]] void bad(const std::string& message, const std::string& field, int status = 400,
                      const std::string& kind = "invalid_argument") {
  throw RequestError{status, message, field, kind};
}

// ---------------------------------------------------------------------------------------------
// What the page needs beyond the library's catalogue: the paper's input hierarchy (§4.3, §5),
// slider ranges and starting values. Slider ranges cover ANSUR II (development subsets, both
// sexes: stature 143.5–198.0 cm, weight 35.8–144.2 kg, span 132.3–212.1 cm, crotch height
// 61.0–102.1 cm, hip breadth 27.7–47.3 cm, arm length 41.8–71.3 cm) rounded outwards; typed
// values may use the catalogue's whole accepted range. Starting values are the subsets' means.
struct InputSpec {
  const char* name;
  int level;  // 1: height & weight; 2: arm span & inseam; 3: hip width & arm length
  double slider_min, slider_max, step;
  double female, male;
};
const std::vector<InputSpec>& input_specs() {
  static const std::vector<InputSpec> specs = {
      {"stature", 1, 140, 205, 0.1, 162.9, 175.6},
      {"weight", 1, 35, 150, 0.1, 67.8, 85.5},
      {"span", 2, 130, 215, 0.1, 166.0, 181.3},
      {"crotch_height", 2, 60, 105, 0.1, 78.2, 84.6},
      {"hip_breadth", 3, 26, 50, 0.1, 35.4, 34.6},
      {"arm_length", 3, 40, 75, 0.1, 55.2, 60.3},
  };
  return specs;
}

// Measurements shown in the table as predictions when they are not inputs.
const std::vector<std::string>& highlighted_predictions() {
  static const std::vector<std::string> names = {"chest_circumference", "waist_circumference",
                                                 "buttock_circumference", "thigh_circumference",
                                                 "neck_circumference", "biacromial_breadth"};
  return names;
}

ordered_json range_json(const MeasurementInfo& info) {
  return {{"min", info.min_edge}, {"max", info.max_edge}, {"unit", edge_unit(info)}};
}

// ---------------------------------------------------------------------------------------------
// Request parsing.

struct BodyRequest {
  std::vector<double> weights;  // /api/mirror-body: the weight changes, percent (mirror_weights)
  std::string model;
  Sex sex = Sex::Female;
  EdgeAvatarRequest edge;  // as the client sent it: canonical name → cm / kg, estimator, noise
  bool include_mesh = true;
  std::string pose = "t";                     // /api/avatar's mesh: t (the rest pose), a or stride
  AvatarFileOptions file;  // exports: bone names, morph targets
};

ordered_json parse_json_body(const std::string& body) {
  if (body.empty()) bad("the request body is empty; send a JSON object", "body");
  return parse_json_object(body, "the request body");
}

std::string string_field(const ordered_json& j, const char* key, const std::string& fallback) {
  if (!j.contains(key) || j[key].is_null()) return fallback;
  if (!j[key].is_string()) bad(std::string(key) + " must be a string", key);
  return j[key].get<std::string>();
}

// Measurement values at the edge (cm, kg), keyed by canonical name, each checked against the
// catalogue's accepted range. Null values are skipped (an empty field on the page).
std::map<std::string, double> parse_measurements(const ordered_json& m) {
  if (!m.is_object()) bad("measurements must be an object of name: value (cm or kg)", "measurements");
  std::map<std::string, double> edge;
  for (const auto& [name, value] : m.items()) {
    if (value.is_null()) continue;
    const MeasurementInfo* info = find_measurement_info(name);
    if (!info) bad("unknown measurement '" + name + "' (GET /api/measurements lists them)", name);
    if (!value.is_number())
      throw Error(ErrorKind::InvalidArgument, info->name + " must be a number in " + edge_unit(*info), info->name);
    if (edge.count(info->name))
      bad(info->name + " was given twice (as '" + name + "' and another alias)", info->name);
    edge[info->name] = value.get<double>();
  }
  return edge;
}

// The library's one way from edge values to an avatar request (the CLI's and Python's too): it
// checks every value and noise SD, naming the field and the range. Values that look like a typing
// mistake (swapped, wrong unit) become a 400 "suspect_values" with what was probably meant,
// unless the client says "force": true.
AvatarRequest checked_request(const EdgeAvatarRequest& edge) {
  try {
    return avatar_request_from_edge(edge);
  } catch (const SuspectInputError& e) {
    ordered_json list = ordered_json::array();
    for (const auto& s : e.suspects())
      list.push_back({{"field", s.field}, {"given", s.given}, {"suggested", round_to(s.suggested, 0.1)}, {"reason", s.reason}});
    ordered_json suggested = ordered_json::object();
    for (const auto& [name, v] : apply_suggestions(edge.measurements, e.suspects())) suggested[name] = round_to(v, 0.1);
    throw RequestError{400, e.what(), e.field(), "suspect_values", {{"suspects", list}, {"suggested_measurements", suggested}}};
  }
}

// The virtual mirror's weight changes (docs/api.md "Mirror bodies"): at most 21, each in the
// accepted range; 0 (the person as measured) always among them; ascending, without repeats.
constexpr size_t kMaxMirrorBodies = 21;
const std::vector<double>& default_mirror_weights() {
  static const std::vector<double> w = {-30, -20, -10, 0, 10, 20, 30};
  return w;
}
std::vector<double> mirror_weights(std::vector<double> w) {
  if (w.size() > kMaxMirrorBodies)
    bad("weights holds at most " + std::to_string(kMaxMirrorBodies) + " values (got " + std::to_string(w.size()) + ")", "weights");
  for (double v : w) check_weight_change(v, "weights");
  w.push_back(0);
  std::sort(w.begin(), w.end());
  w.erase(std::unique(w.begin(), w.end()), w.end());
  if (w.size() > kMaxMirrorBodies)
    bad("weights holds at most " + std::to_string(kMaxMirrorBodies) + " values, 0 included", "weights");
  return w;
}
// "-30,-20,0,7.5" (a query parameter) → numbers; anything else in the list is a 400 naming "weights".
std::vector<double> parse_weight_list(const std::string& text) {
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (out.size() > kMaxMirrorBodies) break;  // refused by mirror_weights; do not parse a huge list
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end != item.c_str() + item.size() || errno == ERANGE)
      bad("weights must be a comma list of percentages, e.g. -30,-20,-10,0,10,20,30 (got '" + item.substr(0, 40) + "')", "weights");
    out.push_back(v);
  }
  return out;
}

enum class BodyEndpoint { Avatar, Export, Mirror };

BodyRequest parse_body_request(const std::string& body, const std::string& default_model, BodyEndpoint endpoint) {
  const ordered_json j = parse_json_body(body);
  const bool allow_mesh_flag = endpoint == BodyEndpoint::Avatar;
  // The message lists exactly what this endpoint takes ("mesh" and "pose" only on /api/avatar).
  std::vector<std::string> known = {"sex", "model", "regressor", "measurements", "noise", "noise_sd", "force"};
  if (allow_mesh_flag) known.insert(known.begin() + 4, {"mesh", "pose"});
  else if (endpoint == BodyEndpoint::Export) known.insert(known.end(), {"skeleton", "morphs"});
  else known.push_back("weights");
  for (const auto& [key, value] : j.items())
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      bad("unknown field '" + key + "' (expected " + list + ")", key);
    }
  BodyRequest r;
  r.sex = parse_sex(string_field(j, "sex", "female"));
  r.model = string_field(j, "model", default_model);
  r.edge.estimator = string_field(j, "regressor", "auto");
  if (r.edge.estimator.empty()) r.edge.estimator = "auto";
  if (!j.contains("measurements")) bad("measurements is required, e.g. {\"stature\": 165, \"weight\": 60}", "measurements");
  r.edge.measurements = parse_measurements(j["measurements"]);
  if (j.contains("force") && !j["force"].is_boolean()) bad("force must be true or false", "force");
  r.edge.force = j.value("force", false);
  if (j.contains("mesh")) {
    if (!j["mesh"].is_boolean()) bad("mesh must be true or false", "mesh");
    r.include_mesh = j["mesh"].get<bool>();
  }
  // The viewer's pose (exports stay in the rest pose, rigged, for the client to pose).
  r.pose = lower(string_field(j, "pose", "t"));
  if (r.pose != "t" && r.pose != "a" && r.pose != "stride") bad("pose must be t (the rest pose), a or stride", "pose");
  // Who measured, for auto (= map), and optional SDs per measurement (cm or kg); values whose
  // noise nobody stated are reproduced as given.
  r.file.skeleton = parse_skeleton_naming(string_field(j, "skeleton", "smpl"), "skeleton");
  if (j.contains("morphs") && !j["morphs"].is_boolean()) bad("morphs must be true or false", "morphs");
  r.file.morphs = j.value("morphs", false);
  if (endpoint == BodyEndpoint::Mirror) {
    std::vector<double> w = default_mirror_weights();
    if (j.contains("weights") && !j["weights"].is_null()) {
      const ordered_json& list = j["weights"];
      if (!list.is_array()) bad("weights must be an array of percentages, e.g. [-30, -20, -10, 0, 10, 20, 30]", "weights");
      w.clear();
      for (const auto& v : list) {
        if (!v.is_number()) bad("weights must hold numbers (percent of body weight)", "weights");
        w.push_back(v.get<double>());
      }
    }
    r.weights = mirror_weights(w);
  }
  r.edge.noise = lower(string_field(j, "noise", "exact"));
  if (r.edge.noise != "exact" && r.edge.noise != "self" && r.edge.noise != "other") bad("noise must be exact, self or other", "noise");
  if (j.contains("noise_sd") && !j["noise_sd"].is_null()) {
    if (!j["noise_sd"].is_object()) bad("noise_sd must be an object of name: SD (cm or kg)", "noise_sd");
    for (const auto& [name, value] : j["noise_sd"].items()) {
      if (!value.is_number()) bad("the noise SD of " + name + " must be a number (cm or kg)", "noise_sd." + name);
      r.edge.noise_sd[name] = value.get<double>();
    }
  }
  checked_request(r.edge);  // every value now, before a model is loaded
  return r;
}

// ---------------------------------------------------------------------------------------------
// Measurement sets (import/export, JSON and CSV; docs/api.md "Measurement sets").

// The library's reader (parse_measurement_set) is the only one: the CLI, capture and this API
// read a set the same way. The set is the client's upload (the library's default origin), so a
// malformed one is a 400; errors about the set as a whole name "measurements" in the library,
// here the request "body".
MeasurementSetFile read_set_body(const std::string& body) {
  try {
    return parse_measurement_set(body);
  } catch (const Error& e) {
    if (e.field() != "measurements") throw;
    throw e.restated(e.what(), "body");
  }
}

std::string models_folder(const ApiOptions& options) {
  return options.models_dir.empty() ? caliper::models_dir() : options.models_dir;
}

// Model families in the models folder: "mannequin-female.npz" … → "mannequin" with its sexes;
// any other .npz file is a model of its own, usable with every sex (the sex then picks the
// weight-from-volume coefficients). Only these names are accepted, never paths.
std::map<std::string, std::vector<std::string>> model_families(const std::string& dir) {
  std::map<std::string, std::vector<std::string>> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    if (e.path().extension() != ".npz") continue;
    const std::string stem = e.path().stem().string();
    bool family = false;
    for (const char* sex : {"female", "male", "neutral"}) {
      const std::string suffix = std::string("-") + sex;
      if (stem.size() > suffix.size() && stem.compare(stem.size() - suffix.size(), suffix.size(), suffix) == 0) {
        out[stem.substr(0, stem.size() - suffix.size())].push_back(sex);
        family = true;
      }
    }
    if (!family) out[stem] = {"female", "male", "neutral"};
  }
  for (auto& [name, sexes] : out) {
    // female, male, neutral order whatever the directory order was.
    std::vector<std::string> ordered;
    for (const char* s : {"female", "male", "neutral"})
      if (std::find(sexes.begin(), sexes.end(), s) != sexes.end()) ordered.push_back(s);
    sexes = ordered;
  }
  return out;
}

// The sexes of `model`, or Error(InvalidArgument, field "model") listing the families found. A
// library Error rather than a RequestError so `caliper serve --model` can report it too.
const std::vector<std::string>& known_family(const std::map<std::string, std::vector<std::string>>& families,
                                             const std::string& model) {
  auto fam = families.find(model);
  if (fam == families.end()) {
    std::string names;
    for (const auto& [n, s] : families) names += (names.empty() ? "" : ", ") + n;
    throw Error(ErrorKind::InvalidArgument,
                "unknown model '" + model + "' (available: " + (names.empty() ? "none — see docs/desktop-tool.md" : names) + ")",
                "model");
  }
  return fam->second;
}

}  // namespace

namespace {
// The error body, with `details` (an object) merged into it.
ApiResponse error_with_details(int status, const std::string& message, const std::string& field, const std::string& kind,
                               const ordered_json& details) {
  ordered_json e;
  e["message"] = message;
  e["field"] = field.empty() ? ordered_json(nullptr) : ordered_json(field);
  const MeasurementInfo* info = field.empty() ? nullptr : find_measurement_info(field);
  e["accepted_range"] = info ? range_json(*info) : ordered_json(nullptr);
  e["kind"] = kind;
  if (details.is_object())
    for (const auto& [k, v] : details.items()) e[k] = v;
  return json_response({{"error", e}}, status);
}
}  // namespace

ApiResponse error_response(int status, const std::string& message, const std::string& field, const std::string& kind) {
  return error_with_details(status, message, field, kind, nullptr);
}

namespace {
// Runs a handler; every error becomes the API's JSON error response (nothing escapes).
template <class Handler>
ApiResponse respond(Handler&& handler) {
  try {
    return handler();
  } catch (const RequestError& e) {
    return error_with_details(e.status, e.message, e.field, e.kind, e.details);
  } catch (const Error& e) {
    return error_response_for_library_error(e, "model_format", "model_io");
  } catch (const std::exception& e) {
    return error_response(500, std::string("internal error: ") + e.what(), {}, "internal");
  }
}
}  // namespace

// ---------------------------------------------------------------------------------------------

struct Api::Impl {
  ApiOptions options;
  std::unique_ptr<CaptureApi> capture;  // /api/sessions… and /api/capture/…

  struct Entry {
    std::once_flag once;
    std::shared_ptr<const BodyModel> model;
    std::unique_ptr<AvatarBuilder> builder;
    std::string topology;  // the JSON body of /api/topology, built once
  };
  mutable std::mutex mutex;
  mutable std::map<std::string, std::shared_ptr<Entry>> entries;

  std::string dir() const { return models_folder(options); }
  std::map<std::string, std::vector<std::string>> families() const { return model_families(dir()); }

  std::shared_ptr<Entry> entry(const std::string& model, Sex sex) const {
    const std::string sex_text = to_string(sex);
    const auto fams = model_families(dir());
    const std::vector<std::string>& sexes = known_family(fams, model);
    if (std::find(sexes.begin(), sexes.end(), sex_text) == sexes.end())
      bad("model '" + model + "' has no " + sex_text + " variant", "sex");
    std::shared_ptr<Entry> e;
    {
      std::lock_guard<std::mutex> lock(mutex);
      auto& slot = entries[model + "/" + sex_text];
      if (!slot) slot = std::make_shared<Entry>();
      e = slot;
    }
    // Loaded once per (model, sex); a failed load throws and the next request tries again.
    // The model file and the maps inside it are the server's own: their errors are 500s.
    std::call_once(e->once, [&] {
      const fs::path family_file = fs::path(dir()) / (model + "-" + sex_text + ".npz");
      const fs::path single_file = fs::path(dir()) / (model + ".npz");
      const std::string path = fs::exists(family_file) ? family_file.string() : single_file.string();
      installation_input([&] {
        auto m = std::make_shared<const BodyModel>(load_model(path, sex));
        e->builder = std::make_unique<AvatarBuilder>(m);
        e->topology = topology_json(*m, model, sex_text);
        e->model = std::move(m);
      });
    });
    return e;
  }

  static std::string topology_json(const BodyModel& m, const std::string& family, const std::string& sex) {
    std::vector<std::uint32_t> faces(static_cast<size_t>(m.face_count()) * 3);
    for (int f = 0; f < m.face_count(); ++f)
      for (int c = 0; c < 3; ++c) faces[size_t(f) * 3 + c] = static_cast<std::uint32_t>(m.faces()(f, c));
    ordered_json j;
    j["model"] = family;
    j["sex"] = sex;
    j["name"] = m.name();
    j["vertex_count"] = m.vertex_count();
    j["face_count"] = m.face_count();
    j["faces"] = base64(faces.data(), faces.size() * sizeof(std::uint32_t));
    j["encoding"] = "uint32 little-endian, base64, 3 per face, counter-clockwise seen from outside";
    j["joint_names"] = m.data().joint_names;
    j["parents"] = m.data().parents;
    ordered_json meta = ordered_json::object();
    for (const auto& [k, v] : m.data().metadata) meta[k] = v;
    j["metadata"] = meta;
    return dump_json(j);
  }

  struct Built {
    std::shared_ptr<Entry> entry;
    Avatar avatar;
    double build_ms = 0;
  };
  // `shape_only`: the body and its joints, no uncertainty and no measuring (the mirror's bodies
  // are shown, not reported; measuring and the vertex SDs would double their cost).
  Built build(const BodyRequest& r, bool shape_only = false) const {
    Built b;
    b.entry = entry(r.model, r.sex);
    AvatarRequest request = checked_request(r.edge);
    if (shape_only) request.vertex_uncertainty = request.measure_avatar = false;
    const auto t0 = std::chrono::steady_clock::now();
    b.avatar = b.entry->builder->build(request);
    b.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return b;
  }

  // ----- endpoints -----

  ApiResponse models() const {
    ordered_json list = ordered_json::array();
    for (const auto& [name, sexes] : families())
      list.push_back({{"name", name}, {"sexes", sexes}, {"default", name == options.default_model}});
    ordered_json regressors = ordered_json::array();
    for (const auto& p : preset_names())
      regressors.push_back({{"name", p}, {"inputs", preset_inputs(p)}, {"description", "the paper's regressor (§3.4.3)"}});
    regressors.push_back({{"name", "auto"}, {"inputs", nullptr},
                          {"description", "the default: noise-aware estimate from every given measurement, with uncertainty"}});
    regressors.push_back({{"name", "map"}, {"inputs", nullptr}, {"description", "the same as auto"}});
    return json_response({{"default_model", options.default_model}, {"models", list}, {"regressors", regressors}});
  }

  ApiResponse measurements() const {
    ordered_json list = ordered_json::array();
    for (const auto& info : measurement_catalogue()) {
      ordered_json m;
      m["name"] = info.name;
      m["label"] = info.label;
      m["unit"] = edge_unit(info);
      m["accepted_range"] = range_json(info);
      m["aliases"] = info.aliases;
      m["ansur_column"] = info.ansur_column.empty() ? ordered_json(nullptr) : ordered_json(info.ansur_column);
      m["paper_candidate"] = info.paper_13;
      m["input"] = nullptr;
      for (const auto& s : input_specs())
        if (info.name == s.name)
          m["input"] = {{"level", s.level}, {"slider", {{"min", s.slider_min}, {"max", s.slider_max}, {"step", s.step}}},
                        {"default", {{"female", s.female}, {"male", s.male}, {"neutral", round_to((s.female + s.male) / 2, 0.1)}}}};
      m["highlight"] = std::find(highlighted_predictions().begin(), highlighted_predictions().end(), info.name) !=
                       highlighted_predictions().end();
      list.push_back(m);
    }
    ordered_json hierarchy = ordered_json::array({ordered_json::array({"stature", "weight"}),
                                                  ordered_json::array({"span", "crotch_height"}),
                                                  ordered_json::array({"hip_breadth", "arm_length"})});
    return json_response({{"measurements", list}, {"hierarchy", hierarchy}});
  }

  ApiResponse topology(const ApiRequest& req) const {
    auto q = [&](const char* key, const std::string& fallback) {
      auto it = req.query.find(key);
      return it == req.query.end() || it->second.empty() ? fallback : it->second;
    };
    const Sex sex = parse_sex(q("sex", "female"));
    auto e = entry(q("model", options.default_model), sex);
    ApiResponse r;
    r.body = e->topology;
    return r;
  }

  ApiResponse avatar(const ApiRequest& req) const {
    const auto t0 = std::chrono::steady_clock::now();
    const BodyRequest r = parse_body_request(req.body, options.default_model, BodyEndpoint::Avatar);
    const Built b = build(r);
    ordered_json j;
    j["report"] = ordered_json::parse(avatar_report_json(b.entry->builder->model(), b.avatar, -1));
    j["report"]["model_family"] = r.model;
    if (r.include_mesh) {
      const BodyModel& model = b.entry->builder->model();
      const Vertices v = r.pose == "a"        ? pose_vertices(model, b.avatar.rest_vertices, a_pose(model))
                         : r.pose == "stride" ? pose_vertices(model, b.avatar.rest_vertices, stride_pose(model))
                                              : b.avatar.rest_vertices;
      std::vector<float> positions(static_cast<size_t>(v.rows()) * 3);
      for (Eigen::Index i = 0; i < v.rows(); ++i)
        for (int c = 0; c < 3; ++c) positions[size_t(i) * 3 + c] = static_cast<float>(v(i, c));
      j["mesh"] = {{"vertex_count", v.rows()},
                   {"positions", base64(positions.data(), positions.size() * sizeof(float))},
                   {"encoding", "float32 little-endian, base64, x y z per vertex, metres, +Y up, facing +Z"},
                   {"pose", r.pose},
                   {"topology", "/api/topology?model=" + r.model + "&sex=" + to_string(r.sex)}};
      if (b.avatar.vertex_sd.size() == v.rows()) {
        // The map estimator's per-vertex SD, for the page's heat map.
        std::vector<float> sd(static_cast<size_t>(v.rows()));
        for (Eigen::Index i = 0; i < v.rows(); ++i) sd[size_t(i)] = static_cast<float>(b.avatar.vertex_sd(i));
        j["mesh"]["vertex_sd"] = base64(sd.data(), sd.size() * sizeof(float));
        j["mesh"]["vertex_sd_encoding"] = "float32 little-endian, base64, one per vertex, metres (posterior SD)";
      }
    }
    j["timing_ms"] = {{"build", round_to(b.build_ms, 0.01)},
                      {"total", round_to(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count(), 0.01)}};
    return json_response(j);
  }

  ApiResponse export_file(const ApiRequest& req, const std::string& kind) const {
    const BodyRequest r = parse_body_request(req.body, options.default_model, BodyEndpoint::Export);
    const Built b = build(r);
    const BodyModel& m = b.entry->builder->model();
    ApiResponse out;
    const std::string stem = "caliper-" + m.name() + "-" + b.avatar.regressor;
    if (const std::optional<AvatarFormat> format = avatar_format_named(kind)) {
      // FBX and OBJ have no registered media type.
      out.content_type = *format == AvatarFormat::Obj ? "text/plain; charset=utf-8"
                         : *format == AvatarFormat::Fbx ? "application/octet-stream"
                                                        : "model/gltf-binary";
      out.body = write_avatar(*format, m, b.avatar, r.file);
      out.download_name = stem + "." + kind;
    } else {
      out.body = avatar_report_json(m, b.avatar);
      out.download_name = stem + "-report.json";
    }
    return out;
  }

  // The virtual mirror's bodies (docs/api.md "Mirror bodies"): the person as measured and with
  // the weight changed, one topology and rig, plain JSON arrays for the WebXR page.
  ApiResponse mirror_bodies(const BodyRequest& r) const {
    const Built original = build(r, /*shape_only=*/true);
    const AvatarBuilder& builder = *original.entry->builder;
    const BodyModel& model = builder.model();
    const std::vector<Avatar> bodies = with_weight_changes(builder, original.avatar, r.weights);
    auto flat = [](const auto& m, double step) {
      std::vector<double> out(static_cast<size_t>(m.rows()) * 3);
      for (Eigen::Index i = 0; i < m.rows(); ++i)
        for (int c = 0; c < 3; ++c) out[size_t(i) * 3 + c] = round_to(m(i, c), step);
      return out;
    };
    const auto size = measure_some(model, {"stature", "weight"}, original.avatar.rest_vertices);
    ordered_json j;
    j["model"] = r.model;
    j["sex"] = to_string(r.sex);
    j["stature_cm"] = round_to(size.at("stature") * 100, 0.1);
    j["weight_kg"] = round_to(size.at("weight"), 0.1);
    j["rest_pose"] = "T";
    j["units"] = "metres, +Y up, facing +Z; weight in kg, BMI in kg/m²";
    j["joint_names"] = model.data().joint_names;
    j["parents"] = model.data().parents;
    std::vector<int> faces(static_cast<size_t>(model.face_count()) * 3);
    for (int f = 0; f < model.face_count(); ++f)
      for (int c = 0; c < 3; ++c) faces[size_t(f) * 3 + c] = model.faces()(f, c);
    j["faces"] = faces;
    const SkinInfluences skin = skin_influences(model);
    ordered_json skin_joints = ordered_json::array(), skin_weights = ordered_json::array();
    for (Eigen::Index v = 0; v < skin.joints.rows(); ++v) {
      skin_joints.push_back({skin.joints(v, 0), skin.joints(v, 1), skin.joints(v, 2), skin.joints(v, 3)});
      skin_weights.push_back({skin.weights(v, 0), skin.weights(v, 1), skin.weights(v, 2), skin.weights(v, 3)});
    }
    j["skin"] = {{"joints", skin_joints}, {"weights", skin_weights}};
    ordered_json list = ordered_json::array(), warnings = ordered_json::array();
    for (size_t i = 0; i < bodies.size(); ++i) {
      const Avatar& b = bodies[i];
      const auto m = measure_some(model, {"stature", "weight"}, b.rest_vertices);
      list.push_back({{"weight_change_pct", r.weights[i]},
                      {"weight_kg", round_to(m.at("weight"), 0.1)},
                      {"bmi", round_to(m.at("weight") / (m.at("stature") * m.at("stature")), 0.1)},
                      {"stature_cm", round_to(m.at("stature") * 100, 0.1)},
                      {"vertices", flat(b.rest_vertices, 1e-4)},
                      {"joints", flat(b.joints, 1e-4)}});
      for (const auto& w : b.warnings) warnings.push_back(w);
    }
    j["bodies"] = list;
    j["warnings"] = warnings;
    return json_response(j);
  }

  ApiResponse mirror_body(const ApiRequest& req) const {
    return mirror_bodies(parse_body_request(req.body, options.default_model, BodyEndpoint::Mirror));
  }

  // GET /api/sessions/{id}/mirror-body, after the capture API let the request read the session.
  ApiResponse session_mirror_body(const MeasurementSetFile& set, const ApiRequest& req) const {
    for (const auto& [key, value] : req.query)
      if (key != "weights") bad("unknown query parameter '" + key + "' (expected weights)", key);
    if (set.edge.empty()) bad("the session has measured nothing yet", "session", 409, "conflict");
    if (!set.sex) bad("the session has no sex yet (the capture page asks for it at the end)", "sex", 409, "conflict");
    BodyRequest r;
    r.model = options.default_model;
    r.sex = *set.sex;
    r.edge.measurements = set.edge;
    r.edge.noise = set.measured_by.value_or("exact");  // who measured, as `caliper avatar --measurements` weighs it
    r.edge.force = true;  // measured by the headset, not typed
    auto w = req.query.find("weights");
    r.weights = mirror_weights(w == req.query.end() ? default_mirror_weights() : parse_weight_list(w->second));
    return mirror_bodies(r);
  }

  ApiResponse import_set(const ApiRequest& req) const {
    return json_response(ordered_json::parse(write_measurement_set_json(read_set_body(req.body))));
  }

  ApiResponse export_set(const ApiRequest& req) const {
    auto it = req.query.find("format");
    const std::string format = it == req.query.end() ? "json" : lower(it->second);
    if (format != "json" && format != "csv") bad("format must be json or csv", "format");
    const ordered_json j = parse_json_body(req.body);
    for (const auto& [key, value] : j.items())
      if (key != "sex" && key != "model" && key != "measurements" && key != "regressor")
        bad("unknown field '" + key + "' (expected sex, model, measurements)", key);
    MeasurementSetFile set;
    if (j.contains("sex") && !j["sex"].is_null()) set.sex = parse_sex(string_field(j, "sex", "female"));
    if (const std::string model = string_field(j, "model", ""); !model.empty()) set.model = model;
    if (!j.contains("measurements")) bad("measurements is required", "measurements");
    set.edge = parse_measurements(j["measurements"]);
    for (const auto& [name, v] : set.edge) edge_to_si(*find_measurement_info(name), v);  // saved as typed; only the ranges apply
    ApiResponse out;
    if (format == "csv") {
      out.content_type = "text/csv; charset=utf-8";
      out.body = write_measurement_set_csv(set);
      out.download_name = "caliper-measurements.csv";
    } else {
      out.body = write_measurement_set_json(set);
      out.download_name = "caliper-measurements.json";
    }
    return out;
  }

  ApiResponse route(const ApiRequest& req) const {
    struct Route {
      const char* method;
      const char* path;
    };
    auto is = [&](const char* method, const char* path) { return req.method == method && req.path == path; };
    if (is_capture_path(req.path)) return capture->handle(req);
    require_utf8(req.body, "the request body");
    if (is("GET", "/api/health")) return json_response({{"status", "ok"}});
    if (is("GET", "/api/models")) return models();
    if (is("GET", "/api/measurements")) return measurements();
    if (is("GET", "/api/topology")) return topology(req);
    if (is("POST", "/api/avatar")) return avatar(req);
    if (is("POST", "/api/export/glb")) return export_file(req, "glb");
    if (is("POST", "/api/export/fbx")) return export_file(req, "fbx");
    if (is("POST", "/api/export/vrm")) return export_file(req, "vrm");
    if (is("POST", "/api/export/obj")) return export_file(req, "obj");
    if (is("POST", "/api/export/report")) return export_file(req, "report");
    if (is("POST", "/api/measurement-set/import")) return import_set(req);
    if (is("POST", "/api/mirror-body")) return mirror_body(req);
    if (is("POST", "/api/measurement-set/export")) return export_set(req);
    static const std::vector<Route> routes = {
        {"GET", "/api/health"}, {"GET", "/api/models"}, {"GET", "/api/measurements"}, {"GET", "/api/topology"},
        {"POST", "/api/avatar"}, {"POST", "/api/export/glb"}, {"POST", "/api/export/fbx"}, {"POST", "/api/export/vrm"}, {"POST", "/api/export/obj"}, {"POST", "/api/export/report"},
        {"POST", "/api/measurement-set/import"}, {"POST", "/api/measurement-set/export"}, {"POST", "/api/mirror-body"}};
    for (const auto& rt : routes)
      if (req.path == rt.path)
        bad(req.method + " is not allowed on " + req.path + " (use " + rt.method + ")", "method", 405, "method_not_allowed");
    bad("no such endpoint: " + req.path + " (see docs/api.md)", "path", 404, "not_found");
  }
};

ApiResponse error_response_for_library_error(const Error& e, const std::string& format_kind,
                                             const std::string& io_kind) {
  if (e.from_installation()) {
    // The server's own file: not the client's fault, and the details (paths, file names, array
    // names) are for the operator, who finds them on standard error, not for the client.
    std::cerr << "caliper serve: error in the server's own files: " << e.what() << "\n";
    const std::string& kind = e.kind() == ErrorKind::Io ? io_kind : format_kind;
    return error_response(500, "the server cannot use one of its own files (" + kind +
                                   "); the request was not at fault; the server's log has the details", {}, kind);
  }
  switch (e.kind()) {
    case ErrorKind::InvalidArgument: return error_response(400, e.what(), e.field(), "invalid_argument");
    case ErrorKind::OutOfRange: return error_response(400, e.what(), e.field(), "out_of_range");
    case ErrorKind::Unsupported: return error_response(422, e.what(), e.field(), "unsupported");
    case ErrorKind::Format:  // a document the client sent (e.g. a measurement set)
    case ErrorKind::Io: return error_response(400, e.what(), e.field(), "invalid_argument");
  }
  return error_response(500, e.what(), e.field(), "internal");
}

void require_known_model(const ApiOptions& options, const std::string& model) {
  known_family(model_families(models_folder(options)), model);
}

Api::Api(ApiOptions options) : impl_(std::make_unique<Impl>()) {
  impl_->options = std::move(options);
  Impl* impl = impl_.get();
  impl_->capture = std::make_unique<CaptureApi>(CaptureApiOptions{
      impl_->options.sessions_database, impl_->options.capture_profiles_file, impl_->options.https, impl_->options.headset_hosts, {},
      [impl](const MeasurementSetFile& set, const ApiRequest& req) {
        return respond([&] { return impl->session_mirror_body(set, req); });
      }});
}
Api::~Api() = default;

ApiResponse Api::handle(const ApiRequest& request) const {
  return respond([&] { return impl_->route(request); });
}

std::vector<std::string> Api::warm_up(const std::string& model, std::string* problems) const {
  std::vector<std::string> ready;
  auto fams = impl_->families();
  auto it = fams.find(model);
  if (it == fams.end()) {
    if (problems) *problems += "model '" + model + "' is not in " + impl_->dir() + "\n";
    return ready;
  }
  for (const auto& sex_text : it->second) {
    try {
      auto e = impl_->entry(model, parse_sex(sex_text));
      for (const auto& p : preset_names()) e->builder->regressor(p, preset_inputs(p));
      ready.push_back(sex_text);
    } catch (const Error& err) {
      if (problems) *problems += model + " (" + sex_text + "): " + err.what() + "\n";
    } catch (const RequestError& err) {
      if (problems) *problems += model + " (" + sex_text + "): " + err.message + "\n";
    }
  }
  return ready;
}

}  // namespace caliper::server
