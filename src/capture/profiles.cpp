// Controller profiles: the tip of the handle in WebXR grip space. Grip space (WebXR Gamepads
// Module): origin at the centre of the closed fist, −Z along the handle towards the thumb side,
// so the bottom end of the handle — the "tip of the wand controller handle" the paper touches
// the body with (§3.1) — lies along +Z. The offsets below are estimates from each controller's
// size (fist centre to the end of the handle); docs/capture.md says how to check and override.
#include "caliper/capture/profiles.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "caliper/errors.h"
#include "gate.h"

namespace caliper::capture {

ProfileRegistry ProfileRegistry::builtin() {
  ProfileRegistry r;
  // Meta Touch controllers: a short handle below the fist (about 5 cm to its end).
  r.add({"oculus-touch", "Oculus Rift CV1 Touch", Eigen::Vector3d(0, -0.005, 0.05)});
  r.add({"oculus-touch-v2", "Oculus Rift S / Quest 1 Touch", Eigen::Vector3d(0, -0.005, 0.05)});
  r.add({"oculus-touch-v3", "Meta Quest 2 Touch", Eigen::Vector3d(0, -0.005, 0.05)});
  r.add({"meta-quest-touch-plus", "Meta Quest 3 / 3S Touch Plus", Eigen::Vector3d(0, -0.005, 0.05)});
  r.add({"meta-quest-touch-pro", "Meta Quest Touch Pro", Eigen::Vector3d(0, -0.005, 0.055)});
  // HTC Vive wand: the paper's device; a long handle, its end about 7 cm from the fist centre.
  r.add({"htc-vive", "HTC Vive wand", Eigen::Vector3d(0, 0, 0.07)});
  r.add({"htc-vive-focus-3", "HTC Vive Focus 3", Eigen::Vector3d(0, -0.005, 0.05)});
  // Valve Index: the strap holds the hand; the end of the handle is about 6 cm below the fist.
  r.add({"valve-index", "Valve Index", Eigen::Vector3d(0, 0, 0.06)});
  // Unknown hardware: the grip point itself (a person can then touch with the fist's centre).
  r.add({"generic-trigger", "Generic controller (grip point)", Eigen::Vector3d::Zero()});
  r.default_id_ = "meta-quest-touch-plus";
  return r;
}

void ProfileRegistry::add(ControllerProfile profile) {
  if (default_id_.empty()) default_id_ = profile.id;
  profiles_[profile.id] = std::move(profile);
}

const ControllerProfile* ProfileRegistry::find(const std::string& id) const {
  auto it = profiles_.find(id);
  return it == profiles_.end() ? nullptr : &it->second;
}

std::string ProfileRegistry::first_known(const std::vector<std::string>& ids) const {
  for (const auto& id : ids)
    if (find(id)) return id;
  return {};
}

void ProfileRegistry::merge_json(const std::string& text) {
  gate("controller profiles", "profiles", [&] { read_json(text); });
}

void ProfileRegistry::read_json(const std::string& text) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(ErrorKind::Format, std::string("controller profiles: not valid JSON: ") + e.what(), "profiles");
  }
  if (!j.is_object() || !j.contains("profiles") || !j["profiles"].is_object())
    throw Error(ErrorKind::Format, "controller profiles: expected {\"profiles\": {\"id\": {\"tip_offset_m\": [x, y, z]}}}", "profiles");
  std::map<std::string, ControllerProfile> added;
  for (const auto& [id, p] : j["profiles"].items()) {
    const std::string field = "profiles." + id + ".tip_offset_m";
    if (id.empty() || !p.is_object() || !p.contains("tip_offset_m") || !p["tip_offset_m"].is_array() || p["tip_offset_m"].size() != 3)
      throw Error(ErrorKind::Format, "controller profiles: " + field + " must be [x, y, z] in metres", field);
    ControllerProfile cp;
    cp.id = id;
    for (int k = 0; k < 3; ++k) {
      const auto& v = p["tip_offset_m"][k];
      if (!v.is_number() || !std::isfinite(v.get<double>()))
        throw Error(ErrorKind::Format, "controller profiles: " + field + " must hold finite numbers", field);
      cp.tip_offset[k] = v.get<double>();
    }
    if (cp.tip_offset.norm() > 0.5)
      throw Error(ErrorKind::Format, "controller profiles: " + field + " is more than 0.5 m from the grip", field);
    cp.label = p.contains("label") && p["label"].is_string() ? p["label"].get<std::string>() : id;
    added[id] = cp;
  }
  std::string def = default_id_;
  if (j.contains("default")) {
    if (!j["default"].is_string()) throw Error(ErrorKind::Format, "controller profiles: default must be a profile id", "default");
    def = j["default"].get<std::string>();
  }
  if (!find(def) && !added.count(def))
    throw Error(ErrorKind::Format, "controller profiles: default '" + def + "' is not a known profile", "default");
  for (auto& [id, p] : added) profiles_[id] = std::move(p);
  default_id_ = def;
}

void ProfileRegistry::merge_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ErrorKind::Io, "cannot read controller profiles '" + path + "'", path);
  std::ostringstream ss;
  ss << in.rdbuf();
  merge_json(ss.str());
}

}  // namespace caliper::capture
