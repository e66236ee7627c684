// Capture endpoints (docs/api.md "Capture sessions"): sessions created by a desktop or a
// headset page, fed with WebXR controller samples, undone/redone, completed with sex and weight,
// exported as measurement sets. Every write, and every read of a session's measurements from
// another machine than the server's, needs the session's pairing code (X-Caliper-Pairing); each
// session accepts a limited number of wrong codes from all clients together, then locks until the
// experimenter's desktop issues a new code (docs/api.md "Pairing").
#include "capture_api.h"

#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <mutex>
#include <utility>
#include <nlohmann/json.hpp>

#include "caliper/capture/body_image_task.h"
#include "caliper/capture/measurement_set.h"
#include "caliper/capture/service.h"
#include "caliper/errors.h"
#include "caliper/vocabulary/catalogue.h"
#include "client_group.h"
#include "json_body.h"
#include "recent_events.h"

namespace caliper::server {

namespace {

using nlohmann::ordered_json;
using namespace caliper::capture;

struct Refusal {
  int status;
  std::string message, field, kind;
};

[[noreturn]] void refuse(int status, const std::string& message, const std::string& field, const std::string& kind = "invalid_argument") {
  throw Refusal{status, message, field, kind};
}

double cm(double metres) { return round_to(metres * 100.0, 0.01); }

ordered_json parse_object(const std::string& body, bool allow_empty) {
  if (body.find_first_not_of(" \t\r\n") == std::string::npos) {
    if (allow_empty) return ordered_json::object();
    refuse(400, "the request body is empty; send a JSON object", "body");
  }
  return parse_json_object(body, "the request body");
}

// The controller profiles the service uses: the built-in ones with the optional file merged in.
ProfileRegistry load_profiles(const std::string& file) {
  ProfileRegistry r = ProfileRegistry::builtin();
  if (!file.empty()) r.merge_file(file);
  return r;
}

void only_fields(const ordered_json& j, std::initializer_list<const char*> known) {
  for (const auto& [key, value] : j.items()) {
    bool ok = false;
    for (const char* k : known) ok = ok || key == k;
    if (!ok) {
      std::string list;
      for (const char* k : known) list += (list.empty() ? "" : ", ") + std::string(k);
      refuse(400, "unknown field '" + key + "' (expected " + list + ")", key);
    }
  }
}

std::string text_field(const ordered_json& j, const char* key, const std::string& fallback) {
  if (!j.contains(key) || j[key].is_null()) return fallback;
  if (!j[key].is_string()) refuse(400, std::string(key) + " must be a string", key);
  return j[key].get<std::string>();
}

std::optional<Sex> sex_field(const ordered_json& j) {
  const std::string s = text_field(j, "sex", "");
  if (s.empty()) return std::nullopt;
  if (s == "female") return Sex::Female;
  if (s == "male") return Sex::Male;
  refuse(400, "sex must be \"female\" or \"male\"", "sex");
}

std::optional<double> weight_field(const ordered_json& j) {
  if (!j.contains("weight_kg") || j["weight_kg"].is_null()) return std::nullopt;
  if (!j["weight_kg"].is_number()) throw Error(ErrorKind::InvalidArgument, "weight_kg must be a number of kilograms", "weight");
  return j["weight_kg"].get<double>();
}

// A finite number, or a 400 naming where it is. JavaScript's JSON.stringify turns NaN and
// Infinity into null, so null is reported as such.
double number_at(const ordered_json& v, const std::string& field, const std::string& where) {
  if (v.is_null()) refuse(400, where + " is null (NaN or Infinity in JavaScript?); it must be a finite number", field);
  if (!v.is_number()) refuse(400, where + " must be a number", field);
  const double d = v.get<double>();
  if (!std::isfinite(d)) refuse(400, where + " must be a finite number", field);
  return d;
}

std::vector<ControllerSample> parse_samples(const ordered_json& arr) {
  if (!arr.is_array()) refuse(400, "samples must be an array of {t, hand, position, orientation, trigger}", "samples");
  if (arr.size() > kMaxSamplesPerBatch)
    refuse(413, "a batch holds at most " + std::to_string(kMaxSamplesPerBatch) + " samples (got " + std::to_string(arr.size()) + ")",
           "samples", "payload_too_large");
  std::vector<ControllerSample> out;
  out.reserve(arr.size());
  for (size_t i = 0; i < arr.size(); ++i) {
    const std::string at = "samples[" + std::to_string(i) + "]";
    const ordered_json& s = arr[i];
    if (!s.is_object()) refuse(400, at + " must be an object", at);
    for (const auto& [key, value] : s.items())
      if (key != "t" && key != "hand" && key != "position" && key != "orientation" && key != "trigger")
        refuse(400, at + ": unknown field '" + key + "' (expected t, hand, position, orientation, trigger)", at + "." + key);
    for (const char* key : {"t", "hand", "position", "orientation", "trigger"})
      if (!s.contains(key)) refuse(400, at + "." + key + " is missing", at + "." + key);
    ControllerSample c;
    c.t = number_at(s["t"], at + ".t", at + ".t");
    if (!s["hand"].is_string()) refuse(400, at + ".hand must be \"left\" or \"right\"", at + ".hand");
    c.hand = parse_hand(s["hand"].get<std::string>(), at + ".hand");
    const ordered_json& p = s["position"];
    if (!p.is_array() || p.size() != 3) refuse(400, at + ".position must be [x, y, z] in metres", at + ".position");
    for (int k = 0; k < 3; ++k) c.position[k] = number_at(p[k], at + ".position", at + ".position[" + std::to_string(k) + "]");
    const ordered_json& q = s["orientation"];
    if (!q.is_array() || q.size() != 4) refuse(400, at + ".orientation must be a quaternion [x, y, z, w]", at + ".orientation");
    for (int k = 0; k < 4; ++k) c.orientation[k] = number_at(q[k], at + ".orientation", at + ".orientation[" + std::to_string(k) + "]");
    c.trigger = number_at(s["trigger"], at + ".trigger", at + ".trigger");
    out.push_back(c);
  }
  return out;
}

ordered_json point_json(const CapturePoint& p) {
  return {{"step", p.step},
          {"repetition", p.repetition},
          {"value_cm", cm(p.value_m)},
          {"hand", to_string(p.hand)},
          {"tip_m", {round_to(p.tip.x(), 1e-5), round_to(p.tip.y(), 1e-5), round_to(p.tip.z(), 1e-5)}},
          {"other_tip_m", {round_to(p.other_tip.x(), 1e-5), round_to(p.other_tip.y(), 1e-5), round_to(p.other_tip.z(), 1e-5)}}};
}

ordered_json session_json(const Session& s, bool with_points) {
  const CaptureProtocol& p = s.protocol;
  ordered_json j;
  j["id"] = s.id;
  j["mode"] = to_string(p.config().mode);
  j["steps"] = to_string(p.config().steps);
  j["created"] = s.created;
  j["profile"] = s.profile;
  j["state"] = to_string(p.state());
  if (const auto st = p.current_step()) {
    j["step"] = {{"name", st->spec.name},
                 {"kind", to_string(st->spec.kind)},
                 {"title", st->spec.title},
                 {"instruction", st->instruction},
                 {"illustration", st->spec.illustration},
                 {"repetition", st->repetition},
                 {"repetitions_needed", st->repetitions_needed},
                 {"points_needed", st->points_needed},
                 {"points_done", st->points_done}};
  } else {
    j["step"] = nullptr;
  }
  j["progress"] = {{"done", p.steps_done()}, {"total", p.steps_total()}};
  j["floor_m"] = p.floor_m() ? ordered_json(round_to(*p.floor_m(), 1e-5)) : ordered_json(nullptr);
  ordered_json values = ordered_json::object();
  for (const auto& v : p.values()) {
    ordered_json reps = ordered_json::array();
    for (double r : v.repetitions_m) reps.push_back(cm(r));
    values[v.name] = {{"value_cm", v.value_m ? ordered_json(cm(*v.value_m)) : ordered_json(nullptr)},
                      {"repetitions_cm", reps},
                      {"rule", v.value_m ? to_string(v.rule) : "need_more"}};
  }
  j["values"] = values;
  j["sex"] = p.sex() ? ordered_json(to_string(*p.sex())) : ordered_json(nullptr);
  j["weight_kg"] = p.weight_kg() ? ordered_json(*p.weight_kg()) : ordered_json(nullptr);
  ordered_json set = ordered_json::object();
  const auto m = p.measurement_set();
  for (const auto& info : measurement_catalogue()) {
    auto it = m.find(info.name);
    if (it != m.end()) set[info.name] = info.unit == Unit::Kilogram ? it->second : round_to(it->second, 0.01);
  }
  j["measurement_set"] = set;
  j["can_undo"] = !p.points().empty();
  j["can_redo"] = !p.redo_points().empty();
  if (with_points) {
    ordered_json pts = ordered_json::array();
    for (const auto& pt : p.points()) pts.push_back(point_json(pt));
    j["points"] = pts;
  }
  return j;
}

ordered_json event_json(const CaptureEvent& e) {
  ordered_json j;
  j["type"] = to_string(e.type);
  j["step"] = e.step;
  if (e.value_cm) j["value_cm"] = round_to(*e.value_cm, 0.01);
  if (!e.reason.empty()) j["reason"] = e.reason;
  return j;
}

// Wrong pairing codes per session and client address: after kMaxFailures within kWindow, that
// client's requests to that session are refused (429) until the window passes: a device typing
// codes wrongly in a burst is paused before it alone spends the session's budget. What bounds
// guessing is that budget (CaptureService: 10 in all), which no change of address escapes. The
// table holds at most kMaxFailureKeys (session, address) pairs.
constexpr int kMaxFailures = 5;
constexpr auto kWindow = std::chrono::seconds(60);
constexpr size_t kMaxFailureKeys = 4096;


// The experimenter's desktop: a client on the server's own machine (loopback, or connected to the
// server's address from that address). Only it may list sessions with their measurements, read a
// session without its code and issue a new code. TCP does not let another machine on the network
// pose as one of these addresses.
bool is_loopback(const std::string& a) {
  return a == "::1" || a.rfind("127.", 0) == 0 || a.rfind("::ffff:127.", 0) == 0;
}
bool is_desktop(const ApiRequest& req) {
  return is_loopback(req.remote_address) || (!req.remote_address.empty() && req.remote_address == req.local_address);
}

// What a device that is not the desktop sees of a session it has no code for: enough to pick it
// from a list and join it, none of the person's data.
ordered_json session_stub_json(const Session& s) {
  return {{"id", s.id},
          {"mode", to_string(s.protocol.config().mode)},
          {"steps", to_string(s.protocol.config().steps)},
          {"created", s.created},
          {"state", to_string(s.protocol.state())}};
}

// ---- Body-image tasks (docs/api.md "Body-image tasks"; the library checks the values).

ordered_json task_json(const BodyImageTask& t) { return ordered_json::parse(body_image_task_json(t)); }

NewBodyImageTask parse_new_task(const ordered_json& j) {
  only_fields(j, {"kind", "instruction", "start_weight_change_pct", "range_pct"});
  NewBodyImageTask t;
  t.kind = parse_task_kind(text_field(j, "kind", "adjust"));
  t.instruction = text_field(j, "instruction", kHowILook);
  if (j.contains("start_weight_change_pct"))
    t.start_weight_change_pct = number_at(j["start_weight_change_pct"], "start_weight_change_pct", "start_weight_change_pct");
  if (j.contains("range_pct")) {
    const ordered_json& r = j["range_pct"];
    if (!r.is_array() || r.size() != 2) refuse(400, "range_pct must be [min, max], percent of body weight", "range_pct");
    t.range_min_pct = number_at(r[0], "range_pct", "range_pct[0]");
    t.range_max_pct = number_at(r[1], "range_pct", "range_pct[1]");
  }
  return t;
}

BodyImageAnswer parse_answer(const ordered_json& j) {
  only_fields(j, {"chosen_weight_change_pct", "shown_at_s", "answered_at_s", "adjustments"});
  for (const char* key : {"chosen_weight_change_pct", "shown_at_s", "answered_at_s"})
    if (!j.contains(key)) refuse(400, std::string(key) + " is required", key);
  BodyImageAnswer a;
  a.chosen_weight_change_pct = number_at(j["chosen_weight_change_pct"], "chosen_weight_change_pct", "chosen_weight_change_pct");
  a.shown_at_s = number_at(j["shown_at_s"], "shown_at_s", "shown_at_s");
  a.answered_at_s = number_at(j["answered_at_s"], "answered_at_s", "answered_at_s");
  if (j.contains("adjustments") && !j["adjustments"].is_null()) {
    const ordered_json& n = j["adjustments"];
    if (!n.is_number_integer() || n.get<long long>() < 0 || n.get<long long>() > 1000000)
      refuse(400, "adjustments must be a whole number in [0, 1000000]", "adjustments");
    a.adjustments = static_cast<int>(n.get<long long>());
  }
  return a;
}

}  // namespace

bool is_capture_path(const std::string& path) {
  return path == "/api/sessions" || path.rfind("/api/sessions/", 0) == 0 || path.rfind("/api/capture/", 0) == 0;
}

struct CaptureApi::Impl {
  explicit Impl(CaptureApiOptions o) : options(std::move(o)) {}
  const CaptureApiOptions options;
  mutable std::mutex open_mutex;
  mutable std::unique_ptr<CaptureService> service_ptr;
  mutable RecentEvents failures{kMaxFailures, kWindow, kMaxFailureKeys};  // by client group and session
  mutable RecentEvents created_per_device{options.creation.per_device, options.creation.device_window, kMaxFailureKeys};
  mutable RecentEvents created_by_devices{options.creation.by_devices, options.creation.devices_window, 1};

  CaptureService& service() const {
    std::lock_guard<std::mutex> lock(open_mutex);
    if (!service_ptr) {
      CaptureServiceOptions o;
      o.database = options.database;
      o.profiles = load_profiles(options.profiles_file);
      try {
        service_ptr = std::make_unique<CaptureService>(std::move(o));
      } catch (const Error& e) {
        // The database is the server's own file: its path is for the operator's log, not the client.
        std::cerr << "caliper serve: capture sessions are unavailable: " << e.what() << "\n";
        refuse(503, "capture sessions are unavailable: the server cannot open its sessions database; the server's log has the details",
               "database", "unavailable");
      }
    }
    return *service_ptr;
  }

  // Refuses (403, 423 or 429) unless the request carries the session's pairing code.
  void require_pairing(const ApiRequest& req, const std::string& id, const char* what = "this write") const {
    const auto now = std::chrono::steady_clock::now();
    const std::string key = client_group(req.remote_address) + " " + id;
    if (failures.full(key, now))
      refuse(429, "too many wrong pairing codes for this session from this device; wait a minute", "pairing_code",
             "too_many_attempts");
    auto it = req.headers.find("x-caliper-pairing");
    if (it == req.headers.end() || it->second.empty())
      refuse(403, std::string(what) + " needs the session's pairing code in the X-Caliper-Pairing header", "pairing_code", "forbidden");
    const PairingCheck check = service().check_pairing(id, it->second);
    switch (check.status) {
      case PairingStatus::Paired:
        return;
      case PairingStatus::NoSession:
        throw Refusal{404, "no capture session '" + id + "'", "id", "not_found"};
      case PairingStatus::Outdated:
        refuse(423,
               "this session's pairing code was stored by an older Caliper in a form that is no longer accepted; the "
               "experimenter must issue a new code from the desktop (Capture page: New code, or `caliper sessions pair " +
                   id + "`)",
               "pairing_code", "pairing_locked");
      case PairingStatus::Locked:
        refuse(423,
               "this session is locked after " + std::to_string(check.max_failures) +
                   " wrong pairing codes and refuses every code, the right one too; the experimenter must issue a new code "
                   "from the desktop (Capture page: New code, or `caliper sessions pair " + id + "`) and pair again",
               "pairing_code", "pairing_locked");
      case PairingStatus::WrongCode:
        if (check.counted) failures.record(key, now);  // a code already counted is not a new guess
        refuse(403,
               "wrong pairing code for this session (" + std::to_string(check.max_failures - check.failures) +
                   " more wrong codes lock it until the experimenter issues a new one)",
               "pairing_code", "forbidden");
    }
  }

  // Reads of a session's data: the desktop, or a device with the session's code.
  void require_read_access(const ApiRequest& req, const std::string& id) const {
    if (is_desktop(req)) return;
    require_pairing(req, id, "reading a session from another device than the server's");
  }

  ApiResponse reissue(const ApiRequest& req, const std::string& id) const {
    if (!is_desktop(req))
      refuse(403,
             "only the experimenter's desktop (a browser on the machine running caliper serve) may issue a new pairing code",
             "pairing_code", "forbidden");
    const std::optional<std::string> code = service().reissue_pairing(id);
    if (!code) return not_found(id);
    auto s = service().find(id);
    if (!s) return not_found(id);
    return json_response({{"session", session_json(*s, true)}, {"pairing_code", *code}});
  }

  [[noreturn]] static ApiResponse not_found(const std::string& id) {
    throw Refusal{404, "no capture session '" + id + "'", "id", "not_found"};
  }

  void exists(const std::string& id) const {
    if (!service().find(id)) not_found(id);
  }

  ApiResponse profiles() const {
    const ProfileRegistry& r = service().profiles();
    ordered_json all = ordered_json::object();
    for (const auto& [id, p] : r.all())
      all[id] = {{"label", p.label}, {"tip_offset_m", {p.tip_offset.x(), p.tip_offset.y(), p.tip_offset.z()}}};
    return json_response({{"profiles", all}, {"default", r.default_id()}});
  }

  static std::string minutes(std::chrono::seconds d) {
    const auto m = std::chrono::duration_cast<std::chrono::minutes>(d).count();
    return m >= 1 ? std::to_string(m) + (m == 1 ? " minute" : " minutes") : std::to_string(d.count()) + " s";
  }

  // Refuses (429) a device over its creation budget or when devices together are over theirs.
  void require_creation_budget(const ApiRequest& req) const {
    if (is_desktop(req)) return;
    const auto now = std::chrono::steady_clock::now();
    if (created_per_device.full(client_group(req.remote_address), now))
      refuse(429,
             "this device has created " + std::to_string(options.creation.per_device) + " capture sessions in the last " +
                 minutes(options.creation.device_window) + "; join an existing session, or create it on the experimenter's desktop",
             "session", "too_many_sessions");
    if (!created_by_devices.try_record("devices", now))
      refuse(429,
             "devices other than the experimenter's desktop have created " + std::to_string(options.creation.by_devices) +
                 " capture sessions in the last " + minutes(options.creation.devices_window) +
                 "; create the session on the experimenter's desktop",
             "session", "too_many_sessions");
    created_per_device.record(client_group(req.remote_address), now);
  }

  // The address for the headset's browser: this server as the client reached it (scheme, port),
  // at each LAN address when it listens on all interfaces, else at the host the client used.
  // `other_devices` says whether another device can open it (not a loopback name).
  ApiResponse headset(const ApiRequest& req) const {
    const auto [host, port] = split_host(req);
    const std::vector<std::string> hosts = options.headset_hosts.empty() ? std::vector<std::string>{host} : options.headset_hosts;
    ordered_json urls = ordered_json::array();
    for (const auto& h : hosts)
      urls.push_back(std::string(options.https ? "https" : "http") + "://" + h + (port.empty() ? "" : ":" + port) + "/capture.html");
    const bool loopback_only = options.headset_hosts.empty() &&
                               (is_loopback(host) || host == "localhost" || host == "[::1]");
    return json_response({{"urls", urls}, {"other_devices", !loopback_only}});
  }

  // The Host header as host and port ("[::1]:8080" → "[::1]", "8080"); the server checked it
  // before routing (host_check.h). Without one, the address the client connected to.
  static std::pair<std::string, std::string> split_host(const ApiRequest& req) {
    const auto it = req.headers.find("host");
    if (it == req.headers.end() || it->second.empty()) return {req.local_address, ""};
    const std::string& h = it->second;
    const size_t colon = h.rfind(':');
    const size_t bracket = h.rfind(']');
    if (colon == std::string::npos || (bracket != std::string::npos && colon < bracket)) return {h, ""};
    return {h.substr(0, colon), h.substr(colon + 1)};
  }

  ApiResponse create(const ApiRequest& req) const {
    const ordered_json j = parse_object(req.body, true);
    only_fields(j, {"mode", "steps", "sex", "weight_kg", "profile"});
    NewSession n;
    n.mode = parse_mode(text_field(j, "mode", "self"));
    n.steps = parse_step_set(text_field(j, "steps", "core"));
    n.sex = sex_field(j);
    n.weight_kg = weight_field(j);
    n.profile = text_field(j, "profile", "");
    require_creation_budget(req);  // after the body is checked: a malformed request spends nothing
    const CaptureService::Created c = service().create(n);
    return json_response({{"session", session_json(c.session, true)}, {"pairing_code", c.pairing_code}}, 201);
  }

  ApiResponse list(const ApiRequest& req) const {
    const bool desktop = is_desktop(req);
    ordered_json arr = ordered_json::array();
    for (const auto& s : service().list()) arr.push_back(desktop ? session_json(s, false) : session_stub_json(s));
    return json_response({{"sessions", arr}});
  }

  ApiResponse samples(const ApiRequest& req, const std::string& id) const {
    const ordered_json j = parse_object(req.body, false);
    only_fields(j, {"profile", "samples"});
    std::vector<std::string> profile;
    if (j.contains("profile") && !j["profile"].is_null()) {
      if (j["profile"].is_string()) profile.push_back(j["profile"].get<std::string>());
      else if (j["profile"].is_array()) {
        for (const auto& p : j["profile"])
          if (p.is_string()) profile.push_back(p.get<std::string>());
          else refuse(400, "profile must be a string or an array of strings", "profile");
      } else refuse(400, "profile must be a string or an array of strings", "profile");
    }
    if (!j.contains("samples")) refuse(400, "samples is required", "samples");
    const std::vector<ControllerSample> batch = parse_samples(j["samples"]);
    auto r = service().feed(id, batch, profile);
    if (!r) return not_found(id);
    ordered_json events = ordered_json::array();
    for (const auto& e : r->events) events.push_back(event_json(e));
    return json_response({{"session", session_json(r->session, true)}, {"events", events}});
  }

  ApiResponse entries(const ApiRequest& req, const std::string& id) const {
    const ordered_json j = parse_object(req.body, false);
    only_fields(j, {"weight_kg", "sex"});
    auto s = service().set_entries(id, weight_field(j), sex_field(j));
    if (!s) return not_found(id);
    return json_response({{"session", session_json(*s, true)}});
  }

  ApiResponse export_set(const ApiRequest& req, const std::string& id) const {
    auto it = req.query.find("format");
    const std::string format = it == req.query.end() ? "json" : it->second;
    if (format != "json" && format != "csv" && format != "tasks-csv")
      refuse(400, "format must be json, csv or tasks-csv", "format");
    exists(id);
    require_read_access(req, id);
    auto s = service().find(id);
    auto tasks = service().tasks(id);
    if (!s || !tasks) return not_found(id);
    const MeasurementSetFile set = measurement_set_of(s->protocol);
    ApiResponse out;
    if (format == "csv") {
      out.content_type = "text/csv; charset=utf-8";
      out.body = write_measurement_set_csv(set);
      out.download_name = "caliper-" + id + ".csv";
    } else if (format == "tasks-csv") {
      out.content_type = "text/csv; charset=utf-8";
      out.body = write_body_image_tasks_csv(*tasks);
      out.download_name = "caliper-" + id + "-tasks.csv";
    } else {
      out.body = write_session_json(set, *tasks);
      out.download_name = "caliper-" + id + ".json";
    }
    return out;
  }

  ApiResponse mirror_body(const ApiRequest& req, const std::string& id) const {
    exists(id);
    require_read_access(req, id);
    auto s = service().find(id);
    if (!s) return not_found(id);
    if (!options.mirror_body) refuse(404, "this server builds no mirror bodies", "path", "not_found");
    return options.mirror_body(measurement_set_of(s->protocol), req);
  }

  static ordered_json tasks_json(const std::vector<BodyImageTask>& tasks) {
    ordered_json list = ordered_json::array();
    ordered_json current = nullptr;
    for (const auto& t : tasks) {
      list.push_back(task_json(t));
      if (t.state == TaskState::Running) current = list.back();
    }
    return {{"tasks", list}, {"current", current}};
  }

  // /api/sessions/{id}/body-image-tasks[/{task}/answer]: the experimenter starts tasks from the
  // desktop, the headset (with the code) reads them and answers.
  ApiResponse body_image_tasks(const ApiRequest& req, const std::string& id, const std::string& rest) const {
    const std::string& m = req.method;
    if (rest.empty()) {
      if (m == "GET") {
        exists(id);
        require_read_access(req, id);
        auto tasks = service().tasks(id);
        if (!tasks) return not_found(id);
        return json_response(tasks_json(*tasks));
      }
      if (m != "POST") refuse(405, m + " is not allowed on " + req.path + " (use GET or POST)", "method", "method_not_allowed");
      exists(id);
      if (!is_desktop(req))
        refuse(403, "only the experimenter's desktop (a browser on the machine running caliper serve) may start a body-image task",
               "session", "forbidden");
      const NewBodyImageTask n = parse_new_task(parse_object(req.body, false));
      auto t = service().start_task(id, n);
      if (!t) return not_found(id);
      return json_response({{"task", task_json(*t)}}, 201);
    }
    const size_t slash = rest.find('/');
    const std::string task_id = rest.substr(0, slash);
    if (slash == std::string::npos || rest.substr(slash + 1) != "answer" || task_id.empty())
      refuse(404, "no such endpoint: " + req.path + " (see docs/api.md)", "path", "not_found");
    if (m != "POST") refuse(405, m + " is not allowed on " + req.path + " (use POST)", "method", "method_not_allowed");
    exists(id);
    require_pairing(req, id, "answering a body-image task");
    const BodyImageAnswer answer = parse_answer(parse_object(req.body, false));
    const CaptureService::AnswerResult r = service().answer_task(id, task_id, answer);
    using Status = CaptureService::AnswerStatus;
    switch (r.status) {
      case Status::Answered: return json_response({{"task", task_json(*r.task)}});
      case Status::NoSession: return not_found(id);
      case Status::NoTask: refuse(404, "session " + id + " has no body-image task '" + task_id + "'", "task_id", "not_found");
      case Status::NotRunning:
        refuse(409, "task " + task_id + " is " + to_string(r.task->state) + "; only the running task takes an answer", "task_id",
               "conflict");
      case Status::NotAdjustable:
        refuse(409, "task " + task_id + " shows a body and takes no answer (only adjust tasks do)", "task_id", "conflict");
    }
    return not_found(id);
  }

  ApiResponse route(const ApiRequest& req) const {
    const std::string& path = req.path;
    const std::string& m = req.method;
    require_utf8(req.body, "the request body");
    if (path == "/api/capture/headset") {
      if (m != "GET") refuse(405, m + " is not allowed on " + path + " (use GET)", "method", "method_not_allowed");
      return headset(req);
    }
    if (path == "/api/capture/profiles") {
      if (m != "GET") refuse(405, m + " is not allowed on " + path + " (use GET)", "method", "method_not_allowed");
      return profiles();
    }
    if (path == "/api/sessions") {
      if (m == "GET") return list(req);
      if (m == "POST") return create(req);
      refuse(405, m + " is not allowed on " + path + " (use GET or POST)", "method", "method_not_allowed");
    }
    const std::string prefix = "/api/sessions/";
    if (path.rfind(prefix, 0) != 0) refuse(404, "no such endpoint: " + path + " (see docs/api.md)", "path", "not_found");
    const std::string rest = path.substr(prefix.size());
    const size_t slash = rest.find('/');
    const std::string id = rest.substr(0, slash);
    const std::string action = slash == std::string::npos ? "" : rest.substr(slash + 1);
    if (id.empty()) refuse(404, "no such endpoint: " + path, "path", "not_found");
    auto allow = [&](const char* method) {
      if (m != method) refuse(405, m + " is not allowed on " + path + " (use " + method + ")", "method", "method_not_allowed");
    };
    auto exists = [&] { this->exists(id); };
    if (action.empty()) {
      if (m == "GET") {
        exists();
        require_read_access(req, id);
        auto s = service().find(id);
        if (!s) return not_found(id);
        return json_response({{"session", session_json(*s, true)}});
      }
      if (m == "DELETE") {
        exists();
        require_pairing(req, id);
        service().remove(id);
        ApiResponse r;
        r.status = 204;
        r.content_type = "application/json";
        return r;
      }
      refuse(405, m + " is not allowed on " + path + " (use GET or DELETE)", "method", "method_not_allowed");
    }
    if (action == "export") {
      allow("GET");
      return export_set(req, id);
    }
    if (action == "mirror-body") {
      allow("GET");
      return mirror_body(req, id);
    }
    if (action == "body-image-tasks" || action.rfind("body-image-tasks/", 0) == 0)
      return body_image_tasks(req, id, action.size() > 17 ? action.substr(17) : "");
    if (action == "pairing") {
      allow("POST");
      return reissue(req, id);
    }
    if (action == "samples" || action == "undo" || action == "redo" || action == "entries") {
      allow("POST");
      exists();
      require_pairing(req, id);
      if (action == "samples") return samples(req, id);
      if (action == "entries") return entries(req, id);
      auto s = action == "undo" ? service().undo(id) : service().redo(id);
      if (!s) return not_found(id);
      return json_response({{"session", session_json(*s, true)}});
    }
    refuse(404, "no such endpoint: " + path + " (see docs/api.md)", "path", "not_found");
  }
};

void check_capture_profiles_file(const std::string& path) { load_profiles(path); }

CaptureApi::CaptureApi(CaptureApiOptions options) : impl_(std::make_unique<Impl>(std::move(options))) {}
CaptureApi::~CaptureApi() = default;

ApiResponse CaptureApi::handle(const ApiRequest& request) const {
  try {
    return impl_->route(request);
  } catch (const Refusal& r) {
    return error_response(r.status, r.message, r.field, r.kind);
  } catch (const Error& e) {
    // Capture requests carry values, never documents: the only files behind a Format or Io error
    // here are the server's own sessions database and controller profiles.
    const bool own_file = e.kind() == ErrorKind::Format || e.kind() == ErrorKind::Io;
    return error_response_for_library_error(own_file ? e.from(ErrorOrigin::Installation) : e, "database_format",
                                            "database_io");
  } catch (const std::exception& e) {
    return error_response(500, std::string("internal error: ") + e.what(), {}, "internal");
  }
}

}  // namespace caliper::server
