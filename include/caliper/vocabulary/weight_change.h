// A change of body weight in percent, as the virtual mirror's body-image tasks speak of it
// (docs/mirror-tasks.md): the accepted range, shared by the bodies built (avatar_weight_change.h)
// and the tasks stored with a capture session (capture/body_image_task.h).
#pragma once
#include <string>

namespace caliper {

// Accepted weight changes, percent of the body's own weight.
constexpr double kMinWeightChangePct = -50;
constexpr double kMaxWeightChangePct = 100;

// Throws Error(InvalidArgument) for NaN or ±inf and Error(OutOfRange) outside
// [kMinWeightChangePct, kMaxWeightChangePct]; both name `field` and the accepted range.
void check_weight_change(double pct, const std::string& field = "weight_change_pct");

}  // namespace caliper
