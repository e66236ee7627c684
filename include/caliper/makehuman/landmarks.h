// Landmarks for Caliper's measurements on MakeHuman's hm08 body (our own definitions).
// Chosen by geometric rules on the reference body (default sliders, T-pose): extremes of the
// surface near the rig's joints, midline points from hm08.mirror, left points as the mirror of
// the right ones. landmarks/makehuman.json records the result; a test checks the two agree.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "caliper/body/mesh.h"
#include "caliper/makehuman/assets.h"
#include "caliper/vocabulary/definitions.h"

namespace caliper::makehuman {

// Landmark name → body vertex index, picked on the reference body of these assets.
// Throws Error(Format) naming the landmark if a rule finds no candidate (not the hm08 mesh).
std::map<std::string, int> pick_landmarks(const Assets& assets);

// The measurements the MakeHuman body supports: the same definitions (names, kinds, landmark
// names) as the built-in body, so both models measure alike.
std::vector<MeasurementDefinition> measurement_definitions();

}  // namespace caliper::makehuman
