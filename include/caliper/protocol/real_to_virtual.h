// Real → virtual measurement maps (paper §3.3): hip width and arm length are taken in another
// posture than the avatar's rest pose, so a per-measurement linear map virtual = slope·real +
// offset is fitted from paired data. Identity by default. File format: JSON
//   {"format": "caliper-real-to-virtual", "version": 1,
//    "maps": {"hip_breadth": {"slope": 0.93, "offset_cm": 1.2, "pairs": 20, "rmse_cm": 0.4}}}
#pragma once
#include <map>
#include <string>

namespace caliper {

struct LinearMap {
  double slope = 1.0;
  double offset = 0.0;  // metres
  int pairs = 0;        // how many pairs it was fitted on (0 = identity / hand-set)
  double rmse = 0.0;    // metres, fit residual
  double apply(double real) const { return slope * real + offset; }
  double invert(double virtual_value) const { return (virtual_value - offset) / slope; }
  bool is_identity() const { return slope == 1.0 && offset == 0.0; }
};

class RealToVirtual {
 public:
  RealToVirtual() = default;  // identity for every measurement
  static RealToVirtual load(const std::string& path);  // throws Error(Io|Format)
  void save(const std::string& path) const;
  static RealToVirtual from_json(const std::string& text);  // throws Error(Format)
  std::string to_json() const;

  // Fits one map per measurement from a CSV with columns measurement,real_cm,virtual_cm.
  static RealToVirtual fit_csv(const std::string& path);

  const LinearMap& map(const std::string& measurement) const;  // identity if absent
  void set(const std::string& measurement, LinearMap map);
  const std::map<std::string, LinearMap>& maps() const { return maps_; }
  // Applies every map to SI values in place.
  void apply(std::map<std::string, double>& values) const;

 private:
  // The readers behind from_json and fit_csv, which are their gates (src/gate.h).
  static RealToVirtual read_json(const std::string& text);
  static RealToVirtual read_pairs_csv(const std::string& path);
  std::map<std::string, LinearMap> maps_;
};

}  // namespace caliper
