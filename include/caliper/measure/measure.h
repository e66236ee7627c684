// Measuring a body of a model: every definition the model carries, on given rest vertices.
#pragma once
#include <map>
#include <string>
#include <vector>

#include "caliper/body/body_model.h"

namespace caliper {

// Value of one definition on rest vertices of `model` (N×3). SI units (m, kg).
// Throws Error(Unsupported) if a section finds no loop (e.g. a landmark off the surface).
double measure(const BodyModel& model, const MeasurementDefinition& definition, const Vertices& rest);
// The same, cutting sections through `section_faces` only: a subset of the model's faces known
// to contain every face the plane can cross (the regressors' corner design narrows it once).
double measure(const BodyModel& model, const MeasurementDefinition& definition, const Vertices& rest,
               const Faces& section_faces);

// A measurement's value with its gradient with respect to the rest vertices: ∂value/∂v as terms
// (vertex, 3-vector) for the few vertices it depends on (weight: a dense 3N vector); a vertex
// may appear more than once (terms add). Exact wherever the value is differentiable. Used to
// linearise measurements in β without finite differences (vertices are linear in β).
struct GradientTerm {
  int vertex = 0;
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
};
struct MeasurementGradient {
  double value = 0;
  std::vector<GradientTerm> terms;
  // Weight depends on every vertex: its gradient comes dense instead, 3N (x0 y0 z0 x1 …), and
  // `terms` is empty.
  Eigen::VectorXd dense;
};
MeasurementGradient measure_with_gradient(const BodyModel& model, const MeasurementDefinition& definition,
                                          const Vertices& rest, const Faces& section_faces);

// All of the model's measurements, by name, SI units.
std::map<std::string, double> measure_all(const BodyModel& model, const Vertices& rest);
// The named ones the model knows (others are skipped), by name, SI units. Sections through the
// same landmark and plane are cut once and shared (chest breadth, depth and circumference).
std::map<std::string, double> measure_some(const BodyModel& model, const std::vector<std::string>& names,
                                           const Vertices& rest);

// What can be measured on a bare mesh without landmarks: stature (vertical extent), volume (m³)
// and weight by the given coefficients. Throws Error(Format) if the mesh is not closed.
struct MeshMeasurements {
  double stature = 0;
  double volume = 0;
  double weight = 0;
};
MeshMeasurements measure_mesh(const Mesh& mesh, const WeightFromVolume& coefficients);

// A person's body given by a user (an OBJ file, arrays), which must be in metres: measure_mesh,
// refused with Error(OutOfRange) naming `field` when the mesh's height is outside the catalogue's
// stature range (a mesh in centimetres or millimetres), with the scale that fixes it.
MeshMeasurements measure_person_mesh(const Mesh& mesh, const WeightFromVolume& coefficients, const std::string& field);
// The same for a mesh that may have `model`'s topology (its vertex count and faces): then every
// measurement the model defines, else measure_person_mesh's stature, volume and weight (by the
// model's volume → weight fit). By canonical name, SI (m, m³, kg). Vertices must be finite and
// faces in range (the caller's conversion checks them).
std::map<std::string, double> measure_person(const BodyModel& model, const Mesh& mesh, const std::string& field);

}  // namespace caliper
