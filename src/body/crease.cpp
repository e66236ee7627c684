#include "caliper/body/crease.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>

#include "caliper/errors.h"

namespace caliper {

std::vector<EdgeBend> dihedral_angles(const Vertices& vertices, const Faces& faces) {
  // Each undirected edge → the faces using it; only edges with exactly two get an angle.
  std::map<std::pair<std::int32_t, std::int32_t>, std::array<Eigen::Index, 3>> uses;  // faces, count in [2]
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::int32_t u = faces(f, k), w = faces(f, (k + 1) % 3);
      auto& entry = uses.try_emplace({std::min(u, w), std::max(u, w)}, std::array<Eigen::Index, 3>{-1, -1, 0}).first->second;
      if (entry[2] < 2) entry[static_cast<size_t>(entry[2])] = f;
      ++entry[2];
    }
  auto normal = [&](Eigen::Index f) -> Eigen::Vector3d {
    const Eigen::Vector3d a = vertices.row(faces(f, 0)), b = vertices.row(faces(f, 1)), c = vertices.row(faces(f, 2));
    return (b - a).cross(c - a);
  };
  std::vector<EdgeBend> bends;
  bends.reserve(uses.size());
  for (const auto& [edge, entry] : uses) {
    if (entry[2] != 2) continue;
    const Eigen::Vector3d n0 = normal(entry[0]), n1 = normal(entry[1]);
    const double len = n0.norm() * n1.norm();
    // atan2 of |n0×n1| and n0·n1 stays accurate near 0° and 180°, where acos does not.
    const double degrees = len > 0 ? std::atan2(n0.cross(n1).norm(), n0.dot(n1)) * 180.0 / 3.14159265358979323846 : 0.0;
    bends.push_back({edge.first, edge.second, degrees});
  }
  return bends;
}

const char* to_string(BodyRegion region) {
  switch (region) {
    case BodyRegion::Torso: return "torso";
    case BodyRegion::HeadNeck: return "head and neck";
    case BodyRegion::Arms: return "arms";
    case BodyRegion::Hands: return "hands";
    case BodyRegion::Legs: return "legs";
    case BodyRegion::Feet: return "feet";
  }
  return "torso";
}

BodyRegion region_of_joint(const std::string& name) {
  auto has = [&](const char* part) { return name.find(part) != std::string::npos; };
  if (has("wrist") || has("hand") || has("thumb") || has("index") || has("middle") || has("ring") || has("pinky"))
    return BodyRegion::Hands;
  if (has("ankle") || has("foot") || has("toe")) return BodyRegion::Feet;
  if (has("collar") || has("shoulder") || has("elbow")) return BodyRegion::Arms;
  if (has("hip") || has("knee")) return BodyRegion::Legs;
  if (has("neck") || has("head") || has("jaw") || has("eye")) return BodyRegion::HeadNeck;
  return BodyRegion::Torso;
}

bool is_feature_region(BodyRegion region) {
  return region == BodyRegion::Hands || region == BodyRegion::Feet || region == BodyRegion::HeadNeck;
}

namespace {

int depth(BodyRegion r) {  // distance from the torso in the body's tree of regions
  return r == BodyRegion::Torso ? 0 : (r == BodyRegion::Hands || r == BodyRegion::Feet) ? 2 : 1;
}

}  // namespace

std::vector<BodyRegion> vertex_regions(const Eigen::SparseMatrix<double, Eigen::RowMajor>& weights,
                                       const std::vector<std::string>& joint_names) {
  std::vector<BodyRegion> joint_region;
  for (const auto& name : joint_names) joint_region.push_back(region_of_joint(name));
  std::vector<BodyRegion> regions(static_cast<size_t>(weights.rows()), BodyRegion::Torso);
  for (Eigen::Index v = 0; v < weights.outerSize(); ++v) {
    double best = -1;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(weights, v); it; ++it)
      if (it.value() > best && static_cast<size_t>(it.col()) < joint_region.size())
        best = it.value(), regions[static_cast<size_t>(v)] = joint_region[static_cast<size_t>(it.col())];
  }
  return regions;
}

std::vector<CreaseRegionSummary> crease_report(const BodyModel& model, const Vertices& rest) {
  return crease_report(rest, model.faces(), vertex_regions(model.data().skin_weights, model.data().joint_names));
}

std::vector<CreaseRegionSummary> crease_report(const Vertices& vertices, const Faces& faces,
                                               const std::vector<BodyRegion>& regions) {
  if (regions.size() != static_cast<size_t>(vertices.rows()))
    throw Error(ErrorKind::InvalidArgument, "one region per vertex needed: " + std::to_string(regions.size()) +
                                                " regions for " + std::to_string(vertices.rows()) + " vertices", "regions");
  std::map<BodyRegion, std::vector<EdgeBend>> by_region;
  for (const EdgeBend& e : dihedral_angles(vertices, faces)) {
    const BodyRegion ra = regions[static_cast<size_t>(e.a)], rb = regions[static_cast<size_t>(e.b)];
    const BodyRegion r = depth(rb) > depth(ra) || (depth(rb) == depth(ra) && rb > ra) ? rb : ra;
    by_region[r].push_back(e);
  }
  std::vector<CreaseRegionSummary> report;
  for (auto& [region, edges] : by_region) {
    CreaseRegionSummary s;
    s.region = region;
    s.edges = static_cast<std::int64_t>(edges.size());
    const auto worst = std::max_element(edges.begin(), edges.end(),
                                        [](const EdgeBend& x, const EdgeBend& y) { return x.degrees < y.degrees; });
    s.worst = *worst;
    s.max_degrees = worst->degrees;
    const size_t k = std::min(edges.size() - 1, static_cast<size_t>(std::floor(0.99 * static_cast<double>(edges.size()))));
    std::nth_element(edges.begin(), edges.begin() + static_cast<std::ptrdiff_t>(k), edges.end(),
                     [](const EdgeBend& x, const EdgeBend& y) { return x.degrees < y.degrees; });
    s.p99_degrees = edges[k].degrees;
    report.push_back(s);
  }
  return report;
}

double smooth_region_max_crease(const std::vector<CreaseRegionSummary>& report) {
  double worst = 0;
  for (const auto& s : report)
    if (!is_feature_region(s.region)) worst = std::max(worst, s.max_degrees);
  return worst;
}

}  // namespace caliper
