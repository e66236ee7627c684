// How a model defines its measurements: through its own landmarks (paper §3.2, §3.4.2).
// A definition is data, stored in the model file, so every model (built-in, MakeHuman, SMPL)
// measures with the same code.
#pragma once
#include <string>
#include <vector>

namespace caliper {

enum class MeasurementKind {
  Height,         // landmarks[0]'s height above the floor (the body's lowest vertex)
  Length,         // polyline through landmarks[0..n): sum of Euclidean segment lengths, rest pose
  Breadth,        // section through landmarks[0] (plane normal `plane_normal`), extent along X
  Depth,          // same section, extent along Z
  // Same section, extent along X of its front half (in front of the middle of its depth): a
  // caliper's blades on the chest's sides, in front of the arms, while the back may be wider.
  FrontBreadth,
  Circumference,  // same section, perimeter of the convex hull of the loop nearest the landmark (a tape)
  Weight,         // a · volume + b (model's coefficients)
};

enum class Axis { X = 0, Y = 1, Z = 2 };

struct MeasurementDefinition {
  std::string name;                    // ANSUR-style name, e.g. "crotch_height"
  MeasurementKind kind = MeasurementKind::Height;
  std::vector<std::string> landmarks;  // landmark names of the model
  Axis plane_normal = Axis::Y;         // for sections: Y = horizontal plane, X = across a T-pose arm
  std::string description;
};

const char* to_string(MeasurementKind kind);
MeasurementKind parse_measurement_kind(const std::string& text);  // throws Error(Format)
const char* to_string(Axis axis);
Axis parse_axis(const std::string& text);                          // throws Error(Format)

}  // namespace caliper
