// The JSON report of an avatar (README "Report format"): model, sex, regressor, β, plausibility,
// and every measurement the model knows, requested beside achieved, in cm and kg.
#pragma once
#include <string>

#include "caliper/avatar.h"

namespace caliper {

std::string avatar_report_json(const BodyModel& model, const Avatar& avatar, int indent = 2);

}  // namespace caliper
