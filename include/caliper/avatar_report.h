// The JSON report of an avatar (docs/cli.md "Report format"): model, sex, regressor, β, plausibility,
// and every measurement the model knows, requested beside achieved, in cm and kg, as a person
// measures them (a mapped measurement adds its rest-pose value, "rest_pose_cm"); "warnings";
// with the "map" estimator also "uncertainty_cm"/"uncertainty_kg" per measurement (posterior SD)
// and an "uncertainty" object (noise setting, per-input fit, β SDs, vertex SD summary).
#pragma once
#include <string>

#include "caliper/avatar.h"
#include "caliper/export/provenance.h"

namespace caliper {

std::string avatar_report_json(const BodyModel& model, const Avatar& avatar, int indent = 2);

// What an exported file says about this avatar: the model's provenance, the regressor and the
// measurements as requested (SI).
Provenance avatar_provenance(const BodyModel& model, const Avatar& avatar);

}  // namespace caliper
