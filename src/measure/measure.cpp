// Virtual measurements on a body (paper §3.2, §3.4.2): heights above the floor, landmark
// distances, plane sections for breadths, depths and tape circumferences, weight from volume.
#include "caliper/measure/measure.h"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "caliper/body/mesh.h"
#include "caliper/errors.h"
#include "caliper/measure/geometry.h"
#include "caliper/vocabulary/catalogue.h"

namespace caliper {

namespace {

Eigen::Vector3d axis_vector(Axis a) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  n(static_cast<int>(a)) = 1.0;
  return n;
}

// The section loop nearest the landmark: a horizontal cut at the thigh also cuts the other leg,
// a cut across an arm may catch the hand; the landmark says which one is meant.
std::vector<SectionPoint> nearest_loop(const BodyModel& model, const MeasurementDefinition& def, const Vertices& rest,
                                       const Faces& faces) {
  if (def.landmarks.empty())
    throw Error(ErrorKind::Format, "measurement '" + def.name + "' needs a landmark", def.name);
  const Eigen::Vector3d p = rest.row(model.landmark(def.landmarks[0])).transpose();
  auto loops = plane_section_points(rest, faces, p, axis_vector(def.plane_normal));
  double best = std::numeric_limits<double>::infinity();
  size_t best_index = loops.size();
  for (size_t i = 0; i < loops.size(); ++i)
    for (const auto& s : loops[i]) {
      const double dist = (s.q - p).squaredNorm();
      if (dist < best) { best = dist; best_index = i; }
    }
  if (best_index == loops.size())
    throw Error(ErrorKind::Unsupported, "measurement '" + def.name + "': the section through landmark '" +
                                            def.landmarks[0] + "' does not cut the body", def.name);
  return std::move(loops[best_index]);
}

// In-plane coordinates: the two axes other than the plane normal, in x, y, z order.
std::pair<int, int> in_plane_axes(Axis normal) {
  switch (normal) {
    case Axis::X: return {1, 2};
    case Axis::Y: return {0, 2};
    case Axis::Z: return {0, 1};
  }
  return {0, 2};
}

using SectionLoop = std::vector<SectionPoint>;

// The loop's points of least and greatest coordinate along `axis` (the first found at a tie).
std::pair<size_t, size_t> extreme_points(const SectionLoop& loop, int axis) {
  size_t lo = 0, hi = 0;
  for (size_t i = 1; i < loop.size(); ++i) {
    if (loop[i].q(axis) < loop[lo].q(axis)) lo = i;
    if (loop[i].q(axis) > loop[hi].q(axis)) hi = i;
  }
  return {lo, hi};
}
using SectionCache = std::map<std::pair<std::string, Axis>, SectionLoop>;

const SectionLoop& cached_loop(const BodyModel& model, const MeasurementDefinition& def, const Vertices& rest,
                               const Faces& faces, SectionCache* cache, SectionLoop& own) {
  if (!cache) return own = nearest_loop(model, def, rest, faces);
  const auto key = std::make_pair(def.landmarks.empty() ? std::string() : def.landmarks[0], def.plane_normal);
  auto it = cache->find(key);
  if (it == cache->end()) it = cache->emplace(key, nearest_loop(model, def, rest, faces)).first;
  return it->second;
}

// Chain rule through a section point q = v_a + t(v_b − v_a), t = d_a / (d_a − d_b), d = n·v − n·p:
// a change of ∂F/∂q = g moves F through both edge ends and, by moving the plane, the landmark p.
void add_section_point_gradient(const SectionPoint& s, const Eigen::Vector3d& g, const Eigen::Vector3d& n,
                                int landmark, const Vertices& rest, std::vector<GradientTerm>& terms) {
  const Eigen::Vector3d va = rest.row(s.a).transpose(), vb = rest.row(s.b).transpose();
  const double c = n.dot(rest.row(landmark).transpose());
  const double da = n.dot(va) - c, db = n.dot(vb) - c, denom = da - db;
  if (denom == 0) return;  // an edge within the plane: the point does not move with it
  const double ge = g.dot(vb - va);
  terms.push_back({s.a, (1 - s.t) * g - n * (ge * db / (denom * denom))});
  terms.push_back({s.b, s.t * g + n * (ge * da / (denom * denom))});
  terms.push_back({landmark, -n * (ge / denom)});
}

// A front breadth (MeasurementKind::FrontBreadth): the loop's extent along X over its part in
// front of the middle of its depth, z ≥ mid. Each extreme is a loop point there or the point
// where a loop edge crosses z = mid; there x = x_a + u·(x_b − x_a), u = (mid − z_a)/(z_b − z_a),
// so it moves with both edge ends and, through mid, with the loop's front and back points. The
// loop is closed (sections of closed meshes are), so its last point joins its first. "Front" is
// +Z: models face +Z (docs/model-format.md).
double front_breadth(const SectionLoop& loop, const Eigen::Vector3d& n, int landmark, const Vertices& rest,
                     std::vector<GradientTerm>* gradient) {
  constexpr int X = 0, Z = 2;
  const auto [back, front] = extreme_points(loop, Z);
  const double mid = 0.5 * (loop[back].q(Z) + loop[front].q(Z));
  struct Extreme { size_t a = 0, b = 0; double u = 0, x = 0; };
  std::optional<Extreme> lo, hi;
  auto consider = [&](size_t a, size_t b, double u) {
    const double x = loop[a].q(X) + u * (loop[b].q(X) - loop[a].q(X));
    if (!lo || x < lo->x) lo = Extreme{a, b, u, x};
    if (!hi || x > hi->x) hi = Extreme{a, b, u, x};
  };
  for (size_t a = 0; a < loop.size(); ++a) {
    const size_t b = (a + 1) % loop.size();
    const double za = loop[a].q(Z), zb = loop[b].q(Z);
    if (za >= mid) consider(a, a, 0.0);
    if ((za - mid) * (zb - mid) < 0) consider(a, b, (mid - za) / (zb - za));
  }
  if (!lo || !hi) throw Error(ErrorKind::Format, "the section has no front half (non-finite coordinates?)", "vertices");
  if (gradient) {
    const Eigen::Vector3d ex = Eigen::Vector3d::UnitX(), ez = Eigen::Vector3d::UnitZ();
    for (const auto& [e, sign] : {std::pair{*hi, 1.0}, std::pair{*lo, -1.0}}) {
      const SectionPoint &pa = loop[e.a], &pb = loop[e.b];
      if (e.a == e.b) { add_section_point_gradient(pa, sign * ex, n, landmark, rest, *gradient); continue; }
      const double dz = pb.q(Z) - pa.q(Z), dx = pb.q(X) - pa.q(X);
      add_section_point_gradient(pa, sign * ((1 - e.u) * ex - dx * (pb.q(Z) - mid) / (dz * dz) * ez), n, landmark, rest, *gradient);
      add_section_point_gradient(pb, sign * (e.u * ex - dx * (mid - pa.q(Z)) / (dz * dz) * ez), n, landmark, rest, *gradient);
      for (size_t extreme : {front, back}) add_section_point_gradient(loop[extreme], sign * 0.5 * dx / dz * ez, n, landmark, rest, *gradient);
    }
  }
  return hi->x - lo->x;
}

// The value of `def` on `rest`; with `gradient`, also ∂value/∂v as sparse terms (exact wherever
// the value is differentiable; at a tie the extreme point found first), or for weight in `dense`.
double measure_with(const BodyModel& model, const MeasurementDefinition& def, const Vertices& rest,
                    const Faces& section_faces, SectionCache* cache, std::vector<GradientTerm>* gradient,
                    Eigen::VectorXd* dense = nullptr) {
  SectionLoop own;
  switch (def.kind) {
    case MeasurementKind::Height: {
      if (def.landmarks.empty()) throw Error(ErrorKind::Format, "height '" + def.name + "' needs a landmark", def.name);
      Eigen::Index lowest = 0;
      const double floor = rest.col(1).minCoeff(&lowest);
      const int top = model.landmark(def.landmarks[0]);
      if (gradient) {
        gradient->push_back({top, Eigen::Vector3d::UnitY()});
        gradient->push_back({static_cast<int>(lowest), -Eigen::Vector3d::UnitY()});
      }
      return rest(top, 1) - floor;
    }
    case MeasurementKind::Length: {
      if (def.landmarks.size() < 2)
        throw Error(ErrorKind::Format, "length '" + def.name + "' needs at least two landmarks", def.name);
      double total = 0;
      for (size_t i = 1; i < def.landmarks.size(); ++i) {
        const int from = model.landmark(def.landmarks[i - 1]), to = model.landmark(def.landmarks[i]);
        const Eigen::Vector3d d = (rest.row(to) - rest.row(from)).transpose();
        const double length = d.norm();
        total += length;
        if (gradient && length > 0) {
          gradient->push_back({to, d / length});
          gradient->push_back({from, -d / length});
        }
      }
      return total;
    }
    case MeasurementKind::Breadth:
    case MeasurementKind::Depth: {
      const SectionLoop& loop = cached_loop(model, def, rest, section_faces, cache, own);
      const int axis = def.kind == MeasurementKind::Breadth ? 0 : 2;
      const auto [lo, hi] = extreme_points(loop, axis);
      if (gradient) {
        const Eigen::Vector3d n = axis_vector(def.plane_normal), e = axis_vector(static_cast<Axis>(axis));
        const int landmark = model.landmark(def.landmarks[0]);
        add_section_point_gradient(loop[hi], e, n, landmark, rest, *gradient);
        add_section_point_gradient(loop[lo], -e, n, landmark, rest, *gradient);
      }
      return loop[hi].q(axis) - loop[lo].q(axis);
    }
    case MeasurementKind::FrontBreadth: {
      if (def.plane_normal != Axis::Y)
        throw Error(ErrorKind::Format, "measurement '" + def.name + "': a front breadth needs a horizontal section (plane_normal y)", def.name);
      const SectionLoop& loop = cached_loop(model, def, rest, section_faces, cache, own);
      return front_breadth(loop, axis_vector(def.plane_normal), model.landmark(def.landmarks[0]), rest, gradient);
    }
    case MeasurementKind::Circumference: {
      // A tape measure follows the convex hull of the section (paper §3.4.2).
      const SectionLoop& loop = cached_loop(model, def, rest, section_faces, cache, own);
      const auto [u, v] = in_plane_axes(def.plane_normal);
      std::vector<Eigen::Vector2d> flat;
      flat.reserve(loop.size());
      for (const auto& s : loop) flat.emplace_back(s.q(u), s.q(v));
      if (!gradient) return convex_hull_perimeter(flat);
      const std::vector<size_t> hull = convex_hull(flat);
      const Eigen::Vector3d n = axis_vector(def.plane_normal);
      const int landmark = model.landmark(def.landmarks[0]);
      double perimeter = 0;
      for (size_t i = 0; i < hull.size(); ++i) {
        // Each hull side pulls its two corners apart along itself.
        const size_t from = hull[i], to = hull[(i + 1) % hull.size()];
        const Eigen::Vector2d side = flat[to] - flat[from];
        const double length = side.norm();
        perimeter += length;
        if (length == 0) continue;
        Eigen::Vector3d g = Eigen::Vector3d::Zero();
        g(u) = side.x() / length;
        g(v) = side.y() / length;
        add_section_point_gradient(loop[to], g, n, landmark, rest, *gradient);
        add_section_point_gradient(loop[from], -g, n, landmark, rest, *gradient);
      }
      return perimeter;
    }
    case MeasurementKind::Weight: {
      const auto& c = model.data().weight_from_volume;
      if (!dense) return c.weight_kg(signed_volume(rest, model.faces()));
      const double volume = signed_volume(rest, model.faces(), *dense);
      *dense *= c.a;
      return c.weight_kg(volume);
    }
  }
  return 0;
}

}  // namespace

double measure(const BodyModel& model, const MeasurementDefinition& def, const Vertices& rest) {
  return measure_with(model, def, rest, model.faces(), nullptr, nullptr);
}

double measure(const BodyModel& model, const MeasurementDefinition& def, const Vertices& rest,
               const Faces& section_faces) {
  return measure_with(model, def, rest, section_faces, nullptr, nullptr);
}

MeasurementGradient measure_with_gradient(const BodyModel& model, const MeasurementDefinition& definition,
                                          const Vertices& rest, const Faces& section_faces) {
  MeasurementGradient out;
  out.value = measure_with(model, definition, rest, section_faces, nullptr, &out.terms, &out.dense);
  return out;
}

std::map<std::string, double> measure_all(const BodyModel& model, const Vertices& rest) {
  std::map<std::string, double> out;
  SectionCache cache;
  for (const auto& def : model.data().measurements) out[def.name] = measure_with(model, def, rest, model.faces(), &cache, nullptr);
  return out;
}

std::map<std::string, double> measure_some(const BodyModel& model, const std::vector<std::string>& names,
                                           const Vertices& rest) {
  std::map<std::string, double> out;
  SectionCache cache;
  for (const auto& name : names)
    if (const MeasurementDefinition* def = model.find_measurement(name)) out[name] = measure_with(model, *def, rest, model.faces(), &cache, nullptr);
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
  m.weight = coefficients.weight_kg(m.volume);
  return m;
}

namespace {
// A body `height` metres tall must be a person's size; a mesh in cm or mm is 100 or 1000 times too tall.
void check_person_height(double height, const std::string& field) {
  const MeasurementInfo& stature = *find_measurement_info("stature");
  const double edge = si_to_edge(stature, height);
  if (edge >= stature.min_edge && edge <= stature.max_edge) return;
  std::ostringstream msg;
  msg << "the mesh is " << height << " m tall, outside the accepted stature range [" << stature.min_edge << ", "
      << stature.max_edge << "] " << edge_unit(stature) << ": meshes are read in metres (scale one in centimetres by "
      << "0.01, in millimetres by 0.001)";
  throw Error(ErrorKind::OutOfRange, msg.str(), field);
}
}  // namespace

MeshMeasurements measure_person_mesh(const Mesh& mesh, const WeightFromVolume& coefficients, const std::string& field) {
  const MeshMeasurements m = measure_mesh(mesh, coefficients);
  check_person_height(m.stature, field);
  return m;
}

std::map<std::string, double> measure_person(const BodyModel& model, const Mesh& mesh, const std::string& field) {
  const bool model_topology = mesh.vertices.rows() == model.vertex_count() &&
                              mesh.faces.rows() == model.faces().rows() && mesh.faces == model.faces();
  if (!model_topology) {
    const MeshMeasurements m = measure_person_mesh(mesh, model.data().weight_from_volume, field);
    return {{"stature", m.stature}, {"volume", m.volume}, {"weight", m.weight}};
  }
  check_person_height(mesh.vertices.col(1).maxCoeff() - mesh.vertices.col(1).minCoeff(), field);
  return measure_all(model, mesh.vertices);
}

}  // namespace caliper
