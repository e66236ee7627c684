// Provenance of an exported avatar: what the body model's metadata says about its origin and
// licence, in the words every export format writes.
#include "caliper/export/provenance.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include "caliper/vocabulary/catalogue.h"
#include "caliper/vocabulary/sex.h"

#ifndef CALIPER_VERSION
#define CALIPER_VERSION "unknown"
#endif

namespace caliper {

namespace {

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string metadata_or(const BodyModel& model, const std::string& key, const std::string& fallback) {
  const auto it = model.data().metadata.find(key);
  return it == model.data().metadata.end() || it->second.empty() ? fallback : it->second;
}

}  // namespace

Provenance model_provenance(const BodyModel& model) {
  Provenance p;
  p.body_model = model.name();
  p.model_source = metadata_or(model, "source", "");
  p.licence = metadata_or(model, "licence", "unknown");
  const std::string format = lower(metadata_or(model, "format", ""));
  const std::string licence = lower(p.licence);
  // An SMPL file's licence travels with everything made from it, whatever its metadata says.
  const bool smpl = format == "smpl" || format == "smplx" || licence.find("smpl") != std::string::npos;
  const bool forbids = licence.find("non-commercial") != std::string::npos ||
                       licence.find("noncommercial") != std::string::npos;
  p.commercial_use = p.licence != "unknown" && !smpl && !forbids;
  p.sex = to_string(model.sex());
  p.caliper_version = CALIPER_VERSION;
  return p;
}

std::string provenance_notice(const Provenance& p) {
  return "Body model " + p.body_model + " (" + p.licence + "); " +
         (p.commercial_use ? "commercial use allowed" : "non-commercial use only") + "; made with Caliper " +
         p.caliper_version;
}

std::vector<ProvenanceMeasurement> measurements_in_edge_units(const Provenance& p) {
  std::vector<ProvenanceMeasurement> out;
  for (const auto& [name, si] : p.measurements) {
    const MeasurementInfo* info = find_measurement_info(name);
    const double value = info ? si_to_edge(*info, si) : si * 100;
    out.push_back({name, std::round(value * 100) / 100, info ? edge_unit(*info) : "cm"});
  }
  return out;
}

std::string measurements_text(const Provenance& p) {
  std::ostringstream s;
  for (const auto& m : measurements_in_edge_units(p))
    s << (s.tellp() > 0 ? ", " : "") << m.name << " " << m.value << " " << m.unit;
  return s.str();
}

}  // namespace caliper
