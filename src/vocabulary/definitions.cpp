#include "caliper/vocabulary/definitions.h"

#include "caliper/errors.h"

namespace caliper {

const char* to_string(MeasurementKind kind) {
  switch (kind) {
    case MeasurementKind::Height: return "height";
    case MeasurementKind::Length: return "length";
    case MeasurementKind::Breadth: return "breadth";
    case MeasurementKind::Depth: return "depth";
    case MeasurementKind::FrontBreadth: return "front_breadth";
    case MeasurementKind::Circumference: return "circumference";
    case MeasurementKind::Weight: return "weight";
  }
  return "height";
}

MeasurementKind parse_measurement_kind(const std::string& text) {
  for (auto k : {MeasurementKind::Height, MeasurementKind::Length, MeasurementKind::Breadth,
                 MeasurementKind::Depth, MeasurementKind::FrontBreadth, MeasurementKind::Circumference,
                 MeasurementKind::Weight})
    if (text == to_string(k)) return k;
  throw Error(ErrorKind::Format,
              "unknown measurement kind '" + text + "' (height, length, breadth, depth, front_breadth, circumference, weight)", "kind");
}

const char* to_string(Axis axis) {
  switch (axis) {
    case Axis::X: return "x";
    case Axis::Y: return "y";
    case Axis::Z: return "z";
  }
  return "y";
}

Axis parse_axis(const std::string& text) {
  if (text == "x") return Axis::X;
  if (text == "y") return Axis::Y;
  if (text == "z") return Axis::Z;
  throw Error(ErrorKind::Format, "unknown axis '" + text + "' (x, y, z)", "plane_normal");
}

}  // namespace caliper
