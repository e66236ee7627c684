// Controller profiles for capture (paper §3.1): where the tip of the handle is in the grip space
// that WebXR's `gripSpace` reports, so the protocol can turn a grip pose into the point that
// touches the body. Profile ids are WebXR input-profile ids ("oculus-touch-v3", "htc-vive", …).
#pragma once
#include <Eigen/Core>
#include <map>
#include <string>
#include <vector>

namespace caliper::capture {

struct ControllerProfile {
  std::string id;           // WebXR input-profile id
  std::string label;        // "Meta Quest 2 Touch"
  Eigen::Vector3d tip_offset = Eigen::Vector3d::Zero();  // tip of the handle in grip space, metres
};

class ProfileRegistry {
 public:
  // The built-in profiles (Meta Touch / Touch Plus / Touch Pro, HTC Vive wand, Valve Index,
  // generic); default "meta-quest-touch-plus".
  static ProfileRegistry builtin();

  // Adds or replaces profiles from JSON text:
  //   {"default"?: "id", "profiles": {"id": {"tip_offset_m": [x, y, z], "label"?: "…"}, …}}
  // Throws Error(Format) naming the field; offsets must be finite and within 0.5 m of the grip.
  void merge_json(const std::string& text);
  void merge_file(const std::string& path);  // throws Error(Io) when unreadable

  // nullptr when unknown.
  const ControllerProfile* find(const std::string& id) const;
  // The first known id of a WebXR profiles list (most specific first), or empty.
  std::string first_known(const std::vector<std::string>& ids) const;
  const std::string& default_id() const { return default_id_; }
  const std::map<std::string, ControllerProfile>& all() const { return profiles_; }
  void add(ControllerProfile profile);

 private:
  void read_json(const std::string& text);  // the reader behind merge_json, which is its gate
  std::map<std::string, ControllerProfile> profiles_;
  std::string default_id_;
};

}  // namespace caliper::capture
