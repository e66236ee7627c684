// Where an exported avatar came from, written into every file (glTF asset.copyright and extras,
// FBX scene info and user properties, VRM meta): the body model, its source and licence,
// whether that licence allows commercial use, the sex, the measurements used and Caliper's
// version. An avatar built on an SMPL model keeps its non-commercial licence this way.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "caliper/body/body_model.h"

namespace caliper {

struct Provenance {
  std::string body_model;        // the model's name
  std::string model_source;      // metadata "source", or ""
  std::string licence;           // metadata "licence", or "unknown"
  bool commercial_use = false;   // true only when the licence is known and does not forbid it
  std::string sex;               // female | male | neutral
  std::string regressor;         // how the shape was found ("" when not from measurements)
  std::map<std::string, double> measurements;  // canonical name → SI value (m, kg), as requested
  std::string caliper_version;
};

// The model's part (the rest stays empty). Commercial use is refused when the licence text says
// "non-commercial", the model came from an SMPL / SMPL-X file, or there is no licence at all.
Provenance model_provenance(const BodyModel& model);

// One line for copyright fields: "Body model <name> (<licence>); non-commercial use only; made
// with Caliper <version>".
std::string provenance_notice(const Provenance& provenance);

// The measurements in the catalogue's units (cm or kg), as a person reads them.
struct ProvenanceMeasurement {
  std::string name;
  double value;
  std::string unit;  // "cm" or "kg"
};
std::vector<ProvenanceMeasurement> measurements_in_edge_units(const Provenance& provenance);
// The same as "name value unit" items joined by ", ".
std::string measurements_text(const Provenance& provenance);

}  // namespace caliper
