// Virtual measurements on a body (paper §3.2, §3.4.2): heights above the floor, landmark
// distances, plane sections for breadths, depths and tape circumferences, weight from volume.
#include "caliper/measure/measure.h"

#include <cmath>
#include <limits>

#include "caliper/body/mesh.h"
#include "caliper/errors.h"
#include "caliper/measure/geometry.h"

namespace caliper {

namespace {

Eigen::Vector3d axis_vector(Axis a) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  n(static_cast<int>(a)) = 1.0;
  return n;
}

// The section loop nearest the landmark: a horizontal cut at the thigh also cuts the other leg,
// a cut across an arm may catch the hand; the landmark says which one is meant.
std::vector<Eigen::Vector3d> nearest_loop(const BodyModel& model, const MeasurementDefinition& def,
                                          const Vertices& rest, const Faces& faces) {
  if (def.landmarks.empty())
    throw Error(ErrorKind::Format, "measurement '" + def.name + "' needs a landmark", def.name);
  const Eigen::Vector3d p = rest.row(model.landmark(def.landmarks[0])).transpose();
  auto loops = plane_section(rest, faces, p, axis_vector(def.plane_normal));
  double best = std::numeric_limits<double>::infinity();
  size_t best_index = loops.size();
  for (size_t i = 0; i < loops.size(); ++i)
    for (const auto& q : loops[i]) {
      const double dist = (q - p).squaredNorm();
      if (dist < best) { best = dist; best_index = i; }
    }
  if (best_index == loops.size())
    throw Error(ErrorKind::Unsupported, "measurement '" + def.name + "': the section through landmark '" +
                                            def.landmarks[0] + "' does not cut the body", def.name);
  return std::move(loops[best_index]);
}

// In-plane coordinates: the two axes other than the plane normal, in x, y, z order.
Eigen::Vector2d in_plane(const Eigen::Vector3d& q, Axis normal) {
  switch (normal) {
    case Axis::X: return {q.y(), q.z()};
    case Axis::Y: return {q.x(), q.z()};
    case Axis::Z: return {q.x(), q.y()};
  }
  return {q.x(), q.z()};
}

double extent(const std::vector<Eigen::Vector3d>& loop, int axis) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& q : loop) { lo = std::min(lo, q(axis)); hi = std::max(hi, q(axis)); }
  return hi - lo;
}

}  // namespace

namespace {

using SectionCache = std::map<std::pair<std::string, Axis>, std::vector<Eigen::Vector3d>>;

const std::vector<Eigen::Vector3d>& cached_loop(const BodyModel& model, const MeasurementDefinition& def,
                                                const Vertices& rest, const Faces& faces, SectionCache* cache,
                                                std::vector<Eigen::Vector3d>& own) {
  if (!cache) return own = nearest_loop(model, def, rest, faces);
  const auto key = std::make_pair(def.landmarks.empty() ? std::string() : def.landmarks[0], def.plane_normal);
  auto it = cache->find(key);
  if (it == cache->end()) it = cache->emplace(key, nearest_loop(model, def, rest, faces)).first;
  return it->second;
}

double measure_with(const BodyModel& model, const MeasurementDefinition& def, const Vertices& rest,
                    const Faces& section_faces, SectionCache* cache) {
  std::vector<Eigen::Vector3d> own;
  switch (def.kind) {
    case MeasurementKind::Height: {
      if (def.landmarks.empty()) throw Error(ErrorKind::Format, "height '" + def.name + "' needs a landmark", def.name);
      const double floor = rest.col(1).minCoeff();
      return rest(model.landmark(def.landmarks[0]), 1) - floor;
    }
    case MeasurementKind::Length: {
      if (def.landmarks.size() < 2)
        throw Error(ErrorKind::Format, "length '" + def.name + "' needs at least two landmarks", def.name);
      double total = 0;
      for (size_t i = 1; i < def.landmarks.size(); ++i)
        total += (rest.row(model.landmark(def.landmarks[i])) - rest.row(model.landmark(def.landmarks[i - 1]))).norm();
      return total;
    }
    case MeasurementKind::Breadth: return extent(cached_loop(model, def, rest, section_faces, cache, own), 0);
    case MeasurementKind::Depth: return extent(cached_loop(model, def, rest, section_faces, cache, own), 2);
    case MeasurementKind::Circumference: {
      const auto& loop = cached_loop(model, def, rest, section_faces, cache, own);
      std::vector<Eigen::Vector2d> flat;
      flat.reserve(loop.size());
      for (const auto& q : loop) flat.push_back(in_plane(q, def.plane_normal));
      return convex_hull_perimeter(flat);
    }
    case MeasurementKind::Weight: {
      const auto& c = model.data().weight_from_volume;
      return c.a * signed_volume(rest, model.faces()) + c.b;
    }
  }
  return 0;
}

}  // namespace

double measure(const BodyModel& model, const MeasurementDefinition& def, const Vertices& rest) {
  return measure_with(model, def, rest, model.faces(), nullptr);
}

double measure(const BodyModel& model, const MeasurementDefinition& def, const Vertices& rest,
               const Faces& section_faces) {
  return measure_with(model, def, rest, section_faces, nullptr);
}

std::map<std::string, double> measure_all(const BodyModel& model, const Vertices& rest) {
  std::map<std::string, double> out;
  SectionCache cache;
  for (const auto& def : model.data().measurements) out[def.name] = measure_with(model, def, rest, model.faces(), &cache);
  return out;
}

std::map<std::string, double> measure_some(const BodyModel& model, const std::vector<std::string>& names,
                                           const Vertices& rest) {
  std::map<std::string, double> out;
  SectionCache cache;
  for (const auto& name : names)
    if (const MeasurementDefinition* def = model.find_measurement(name)) out[name] = measure_with(model, *def, rest, model.faces(), &cache);
  return out;
}

MeshMeasurements measure_mesh(const Mesh& mesh, const WeightFromVolume& coefficients) {
  if (mesh.vertices.rows() < 4 || mesh.faces.rows() < 4)
    throw Error(ErrorKind::Format, "mesh has too few vertices or faces to enclose a volume", "mesh");
  const MeshCheck check = check_mesh(mesh.faces, mesh.vertices.rows());
  if (!check.closed)
    throw Error(ErrorKind::Format, "mesh is not closed (" + std::to_string(check.boundary_edges) +
                                       " boundary edges, " + std::to_string(check.nonmanifold_edges) +
                                       " non-manifold edges): its volume is undefined", "mesh");
  MeshMeasurements m;
  m.stature = mesh.vertices.col(1).maxCoeff() - mesh.vertices.col(1).minCoeff();
  m.volume = signed_volume(mesh.vertices, mesh.faces);
  if (!check.consistently_oriented)
    throw Error(ErrorKind::Format, "mesh faces are not consistently oriented: its volume is undefined", "mesh");
  if (m.volume < 0)
    throw Error(ErrorKind::Format, "mesh faces point inwards (negative volume); flip the winding", "mesh");
  m.weight = coefficients.a * m.volume + coefficients.b;
  return m;
}

}  // namespace caliper
