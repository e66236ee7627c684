// Volume by signed tetrahedra and tape-measure sections (paper §3.4.2).
#include "caliper/measure/geometry.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

namespace caliper {

double signed_volume(const Vertices& vertices, const Faces& faces) {
  // Each face with the origin forms a tetrahedron; outward faces sum to the enclosed volume.
  double six_volume = 0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const auto a = vertices.row(faces(f, 0)), b = vertices.row(faces(f, 1)), c = vertices.row(faces(f, 2));
    six_volume += a(0) * (b(1) * c(2) - b(2) * c(1)) - a(1) * (b(0) * c(2) - b(2) * c(0)) +
                  a(2) * (b(0) * c(1) - b(1) * c(0));
  }
  return six_volume / 6.0;
}

std::vector<std::vector<Eigen::Vector3d>> plane_section(const Vertices& vertices, const Faces& faces,
                                                        const Eigen::Vector3d& point,
                                                        const Eigen::Vector3d& normal) {
  const Eigen::Vector3d n = normal.normalized();
  // Signed distances; vertices exactly on the plane are nudged to one side so every crossing is
  // an edge crossing and loops stay well-formed (a landmark vertex often lies on the plane).
  const Eigen::Index nv = vertices.rows();
  std::vector<double> d(static_cast<size_t>(nv));
  for (Eigen::Index v = 0; v < nv; ++v) {
    double s = (vertices.row(v).transpose() - point).dot(n);
    if (s == 0.0) s = 1e-12;
    d[static_cast<size_t>(v)] = s;
  }
  auto edge_key = [](std::int64_t a, std::int64_t b) {
    if (a > b) std::swap(a, b);
    return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint64_t>(b);
  };
  // Each crossed face contributes one segment between two crossed edges. Link segments by edge.
  std::unordered_map<std::uint64_t, std::vector<std::uint64_t>> adjacency;  // edge → neighbouring edges
  std::unordered_map<std::uint64_t, Eigen::Vector3d> crossing;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    std::uint64_t crossed[2];
    int count = 0;
    for (int k = 0; k < 3; ++k) {
      const std::int64_t a = faces(f, k), b = faces(f, (k + 1) % 3);
      const double da = d[static_cast<size_t>(a)], db = d[static_cast<size_t>(b)];
      if ((da < 0) == (db < 0)) continue;
      const std::uint64_t key = edge_key(a, b);
      if (!crossing.count(key)) {
        const double t = da / (da - db);
        crossing[key] = vertices.row(a).transpose() + t * (vertices.row(b) - vertices.row(a)).transpose();
      }
      if (count < 2) crossed[count] = key;
      ++count;
    }
    if (count == 2) {
      adjacency[crossed[0]].push_back(crossed[1]);
      adjacency[crossed[1]].push_back(crossed[0]);
    }
  }
  std::vector<std::vector<Eigen::Vector3d>> loops;
  std::unordered_map<std::uint64_t, bool> visited;
  // Walk in a deterministic order (sorted keys) so results never depend on hash order.
  std::vector<std::uint64_t> keys;
  keys.reserve(adjacency.size());
  for (const auto& kv : adjacency) keys.push_back(kv.first);
  std::sort(keys.begin(), keys.end());
  for (std::uint64_t start : keys) {
    if (visited[start]) continue;
    std::vector<Eigen::Vector3d> loop;
    std::uint64_t prev = start, cur = start;
    visited[start] = true;
    loop.push_back(crossing[start]);
    for (;;) {
      const auto& nb = adjacency[cur];
      std::uint64_t next = cur;
      for (std::uint64_t c : nb)
        if (c != prev && !visited[c]) { next = c; break; }
      if (next == cur) break;  // closed (back at start) or open at a boundary
      visited[next] = true;
      loop.push_back(crossing[next]);
      prev = cur;
      cur = next;
    }
    if (loop.size() >= 3) loops.push_back(std::move(loop));
  }
  return loops;
}

double convex_hull_perimeter(const std::vector<Eigen::Vector2d>& input) {
  if (input.size() < 2) return 0;
  std::vector<Eigen::Vector2d> p = input;
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Eigen::Vector2d> hull(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {  // lower hull
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i-- > 0;) {  // upper hull
    while (k >= t && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  hull.resize(k - 1);
  double perimeter = 0;
  for (size_t i = 0; i < hull.size(); ++i) perimeter += (hull[(i + 1) % hull.size()] - hull[i]).norm();
  return perimeter;
}

}  // namespace caliper
