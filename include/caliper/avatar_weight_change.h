// The same person heavier or lighter at the same stature: the bodies a body-image task shows
// (the virtual mirror, docs/mirror-tasks.md; the paper's method-of-adjustment task, §4.3,
// Fig. 14, varies the avatar's weight). Each body is built by the project's estimator, not
// scaled: the skeleton's measurements stay, weight changes, and the estimator decides how the
// girths follow.
#pragma once
#include <string>
#include <vector>

#include "caliper/avatar.h"
#include "caliper/vocabulary/weight_change.h"

namespace caliper {

// Whether a change of body weight changes the measurement: weight itself, girths
// (circumferences), depths and the soft-tissue breadths (hip, chest, waist). Heights, lengths,
// spans and the bony breadths (shoulders between the acromions, head, hand, foot) are the
// skeleton's and stay.
bool follows_body_weight(const std::string& measurement);

// `original` (built by `builder`) with its weight changed by `pct` percent at the same stature,
// one body per entry of `pcts`, in that order. Each is β_original + (β(p) − β(0)), where β(p)
// is the estimator's body (map, exact) for the original body's own stature and skeletal lengths
// among `original.requested`, with weight = the original body's weight · (1 + p/100): the change
// a plausible person of that build shows, added to the person's own shape, so 0 % is exactly
// the original and neighbouring bodies differ only by the change. Each returned Avatar has
// its rest vertices, joints, plausibility and (when `original.achieved` is not empty) every
// measurement; `requested` holds the kept lengths and the weight asked for; uncertainty fields
// are empty; a warning says when the body could not reach the weight asked (outside the
// model's population). Throws as check_weight_change (vocabulary/weight_change.h) for a bad
// entry, before building anything.
std::vector<Avatar> with_weight_changes(const AvatarBuilder& builder, const Avatar& original, const std::vector<double>& pcts);
Avatar with_weight_change(const AvatarBuilder& builder, const Avatar& original, double pct);

}  // namespace caliper
