// Volume by signed tetrahedra and tape-measure sections (paper §3.4.2).
#include "caliper/measure/geometry.h"

#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>

namespace caliper {

namespace {
// out += x × y
void add_cross(double* out, const double* x, const double* y) {
  out[0] += x[1] * y[2] - x[2] * y[1];
  out[1] += x[2] * y[0] - x[0] * y[2];
  out[2] += x[0] * y[1] - x[1] * y[0];
}
// Six times the signed volume: each face with the origin forms a tetrahedron, and outward faces
// sum to the enclosed volume. With kGradient, also adds each face's b × c, c × a, a × b to
// `gradient` at a, b, c (six times ∂V/∂v). Raw row-major storage: this loop runs for every
// corner body of the regressors (§3.4.3) and every step of the estimator.
template <bool kGradient>
double six_volume(const Vertices& vertices, const Faces& faces, double* gradient) {
  const double* v = vertices.data();
  const std::int32_t* f = faces.data();
  double sum = 0;
  for (Eigen::Index i = 0; i < faces.rows(); ++i, f += 3) {
    const double* a = v + 3 * f[0];
    const double* b = v + 3 * f[1];
    const double* c = v + 3 * f[2];
    sum += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
    if constexpr (kGradient) {
      add_cross(gradient + 3 * f[0], b, c);
      add_cross(gradient + 3 * f[1], c, a);
      add_cross(gradient + 3 * f[2], a, b);
    }
  }
  return sum;
}
}  // namespace

double signed_volume(const Vertices& vertices, const Faces& faces) {
  return six_volume<false>(vertices, faces, nullptr) / 6.0;
}

double signed_volume(const Vertices& vertices, const Faces& faces, Eigen::VectorXd& gradient) {
  gradient.setZero(vertices.size());
  const double six = six_volume<true>(vertices, faces, gradient.data());
  gradient /= 6.0;
  return six / 6.0;
}

std::vector<std::vector<SectionPoint>> plane_section_points(const Vertices& vertices, const Faces& faces,
                                                            const Eigen::Vector3d& point,
                                                            const Eigen::Vector3d& normal) {
  const Eigen::Vector3d n = normal.normalized();
  // Signed distances; vertices exactly on the plane are nudged to one side so every crossing is
  // an edge crossing and loops stay well-formed (a landmark vertex often lies on the plane).
  const Eigen::Index nv = vertices.rows();
  std::vector<double> d(static_cast<size_t>(nv));
  const double* p = vertices.data();
  const double offset = point.dot(n);
  for (Eigen::Index v = 0; v < nv; ++v, p += 3) {
    const double s = p[0] * n.x() + p[1] * n.y() + p[2] * n.z() - offset;
    d[static_cast<size_t>(v)] = s == 0.0 ? 1e-12 : s;
  }
  auto edge_key = [](std::uint64_t a, std::uint64_t b) { return a < b ? (a << 32) | b : (b << 32) | a; };
  // Each crossed face gives one segment joining its two crossed edges. Sorted vectors instead of
  // hash maps: the cut touches a few hundred faces of many thousands, and order stays deterministic.
  std::vector<std::pair<std::uint64_t, std::uint64_t>> segments;
  const std::int32_t* fp = faces.data();
  for (Eigen::Index f = 0; f < faces.rows(); ++f, fp += 3) {
    const std::uint64_t v0 = static_cast<std::uint64_t>(fp[0]), v1 = static_cast<std::uint64_t>(fp[1]),
                        v2 = static_cast<std::uint64_t>(fp[2]);
    const bool s0 = d[v0] < 0, s1 = d[v1] < 0, s2 = d[v2] < 0;
    if (s0 == s1 && s1 == s2) continue;
    std::uint64_t crossed[2];
    int count = 0;
    if (s0 != s1) crossed[count++] = edge_key(v0, v1);
    if (s1 != s2) crossed[count++] = edge_key(v1, v2);
    if (s2 != s0 && count < 2) crossed[count++] = edge_key(v2, v0);
    segments.push_back({crossed[0], crossed[1]});
  }
  std::vector<std::uint64_t> edges;
  edges.reserve(segments.size() * 2);
  for (const auto& [a, b] : segments) { edges.push_back(a); edges.push_back(b); }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  auto index_of = [&](std::uint64_t key) {
    return static_cast<size_t>(std::lower_bound(edges.begin(), edges.end(), key) - edges.begin());
  };
  // On a closed manifold each crossed edge borders exactly two crossed faces: two neighbours.
  constexpr size_t kNone = static_cast<size_t>(-1);
  std::vector<std::array<size_t, 2>> neighbours(edges.size(), {kNone, kNone});
  auto link = [&](size_t a, size_t b) {
    auto& slot = neighbours[a];
    if (slot[0] == kNone) slot[0] = b; else if (slot[1] == kNone) slot[1] = b;
  };
  for (const auto& [a, b] : segments) {
    const size_t ia = index_of(a), ib = index_of(b);
    link(ia, ib);
    link(ib, ia);
  }
  auto crossing = [&](std::uint64_t key) {
    SectionPoint s;
    s.a = static_cast<int>(key >> 32);
    s.b = static_cast<int>(key & 0xffffffffu);
    const double da = d[static_cast<size_t>(s.a)], db = d[static_cast<size_t>(s.b)];
    s.t = da / (da - db);
    s.q = vertices.row(s.a).transpose() + s.t * (vertices.row(s.b) - vertices.row(s.a)).transpose();
    return s;
  };
  std::vector<std::vector<SectionPoint>> loops;
  std::vector<char> visited(edges.size(), 0);
  for (size_t start = 0; start < edges.size(); ++start) {
    if (visited[start]) continue;
    std::vector<SectionPoint> loop;
    size_t prev = kNone, cur = start;
    while (cur != kNone && !visited[cur]) {
      visited[cur] = 1;
      loop.push_back(crossing(edges[cur]));
      const size_t next = neighbours[cur][0] != prev ? neighbours[cur][0] : neighbours[cur][1];
      prev = cur;
      cur = next;
    }
    if (loop.size() >= 3) loops.push_back(std::move(loop));
  }
  return loops;
}

std::vector<std::vector<Eigen::Vector3d>> plane_section(const Vertices& vertices, const Faces& faces,
                                                        const Eigen::Vector3d& point,
                                                        const Eigen::Vector3d& normal) {
  std::vector<std::vector<Eigen::Vector3d>> loops;
  for (const auto& crossings : plane_section_points(vertices, faces, point, normal)) {
    auto& loop = loops.emplace_back();
    loop.reserve(crossings.size());
    for (const auto& s : crossings) loop.push_back(s.q);
  }
  return loops;
}

std::vector<size_t> convex_hull(const std::vector<Eigen::Vector2d>& p) {
  if (p.size() < 2) return std::vector<size_t>(p.size(), 0);
  std::vector<size_t> order(p.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t i, size_t j) {
    return p[i].x() < p[j].x() || (p[i].x() == p[j].x() && p[i].y() < p[j].y());
  });
  auto cross = [&](size_t o, size_t a, size_t b) {
    return (p[a].x() - p[o].x()) * (p[b].y() - p[o].y()) - (p[a].y() - p[o].y()) * (p[b].x() - p[o].x());
  };
  std::vector<size_t> hull(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < order.size(); ++i) {  // lower hull
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], order[i]) <= 0) --k;
    hull[k++] = order[i];
  }
  for (size_t i = order.size() - 1, t = k + 1; i-- > 0;) {  // upper hull
    while (k >= t && cross(hull[k - 2], hull[k - 1], order[i]) <= 0) --k;
    hull[k++] = order[i];
  }
  hull.resize(k - 1);
  return hull;
}

double convex_hull_perimeter(const std::vector<Eigen::Vector2d>& points) {
  if (points.size() < 2) return 0;
  const std::vector<size_t> hull = convex_hull(points);
  double perimeter = 0;
  for (size_t i = 0; i < hull.size(); ++i) perimeter += (points[hull[(i + 1) % hull.size()]] - points[hull[i]]).norm();
  return perimeter;
}

}  // namespace caliper
