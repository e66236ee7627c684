#include "caliper/body/mesh.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_map>
#include <vector>

namespace caliper {

Vertices vertex_normals(const Vertices& vertices, const Faces& faces) {
  Vertices normals = Vertices::Zero(vertices.rows(), 3);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d a = vertices.row(faces(f, 0)), b = vertices.row(faces(f, 1)), c = vertices.row(faces(f, 2));
    // Every corner's two edges span the same cross product n (|n| = |e1| |e2| sin of the corner's
    // angle); the corner's weight divides it by its two edges' squared lengths.
    const Eigen::Vector3d n = (b - a).cross(c - a);
    const double ab = (b - a).squaredNorm(), bc = (c - b).squaredNorm(), ca = (a - c).squaredNorm();
    const std::array<double, 3> edge_products = {ab * ca, ab * bc, bc * ca};  // at a, b, c
    for (int k = 0; k < 3; ++k)
      if (edge_products[static_cast<size_t>(k)] > 0) normals.row(faces(f, k)) += (n / edge_products[static_cast<size_t>(k)]).transpose();
  }
  for (Eigen::Index v = 0; v < normals.rows(); ++v) {
    const double len = normals.row(v).norm();
    if (len > 0) normals.row(v) /= len; else normals.row(v) << 0, 1, 0;
  }
  return normals;
}

MeshCheck check_mesh(const Faces& faces, std::int64_t vertex_count) {
  MeshCheck result;
  // Directed edge counts: a closed, consistently oriented surface uses each directed edge once
  // and its reverse once.
  std::unordered_map<std::uint64_t, int> directed;
  directed.reserve(static_cast<size_t>(faces.rows()) * 3);
  std::vector<char> used(static_cast<size_t>(std::max<std::int64_t>(vertex_count, 0)), 0);
  auto key = [](std::int64_t a, std::int64_t b) { return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint64_t>(b); };
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const std::int64_t v[3] = {faces(f, 0), faces(f, 1), faces(f, 2)};
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) ++result.degenerate_faces;
    for (int k = 0; k < 3; ++k) {
      if (v[k] >= 0 && v[k] < vertex_count) used[static_cast<size_t>(v[k])] = 1;
      ++directed[key(v[k], v[(k + 1) % 3])];
    }
  }
  bool oriented = true;
  for (const auto& [k, count] : directed) {
    const std::int64_t a = static_cast<std::int64_t>(k >> 32), b = static_cast<std::int64_t>(k & 0xffffffffu);
    const auto rev = directed.find(key(b, a));
    const int reverse = rev == directed.end() ? 0 : rev->second;
    if (count > 1 || reverse > 1) oriented = false;
    if (a < b || reverse == 0) {  // count each undirected edge once
      const int total = count + reverse;
      if (total == 1) ++result.boundary_edges;
      else if (total > 2) ++result.nonmanifold_edges;
      if (total == 2 && count != 1) oriented = false;
    }
  }
  result.unused_vertices = std::count(used.begin(), used.end(), 0);
  result.closed = result.boundary_edges == 0 && result.nonmanifold_edges == 0;
  result.consistently_oriented = result.closed && oriented;
  // Vertex manifoldness: the faces around each vertex form one fan (one cycle of edges).
  bool fans_ok = result.closed && result.degenerate_faces == 0;
  if (fans_ok) {
    // For each vertex, link each "incoming" neighbour to the "outgoing" one within each face; a
    // single cycle means one disc.
    std::vector<std::vector<std::pair<std::int32_t, std::int32_t>>> fan(static_cast<size_t>(vertex_count));
    for (Eigen::Index f = 0; f < faces.rows(); ++f)
      for (int k = 0; k < 3; ++k)
        fan[static_cast<size_t>(faces(f, k))].push_back({faces(f, (k + 1) % 3), faces(f, (k + 2) % 3)});
    for (auto& links : fan) {
      if (links.empty()) continue;
      std::unordered_map<std::int32_t, std::int32_t> next;
      for (auto [a, b] : links) next[a] = b;
      if (next.size() != links.size()) { fans_ok = false; break; }
      std::int32_t start = links[0].first, cur = start;
      size_t steps = 0;
      do {
        auto it = next.find(cur);
        if (it == next.end()) { steps = links.size() + 1; break; }
        cur = it->second;
        ++steps;
      } while (cur != start && steps <= links.size());
      if (steps != links.size()) { fans_ok = false; break; }
    }
  }
  result.manifold = fans_ok;
  return result;
}


namespace {

// Does the segment p→q pass through the triangle abc (Möller–Trumbore, open segment)?
bool segment_hits_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& a,
                           const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d d = q - p, e1 = b - a, e2 = c - a;
  const Eigen::Vector3d h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-18) return false;  // parallel to the plane
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = p - a;
  const double u = inv * s.dot(h);
  if (u < 0 || u > 1) return false;
  const Eigen::Vector3d qv = s.cross(e1);
  const double v = inv * d.dot(qv);
  if (v < 0 || u + v > 1) return false;
  const double t = inv * e2.dot(qv);
  return t > 0 && t < 1;
}

// A face's box (metres, and in grid cells) and its plane (unnormalised normal n, offset n·a).
struct FaceInGrid {
  Eigen::Vector3d box_lo, box_hi;
  std::array<int, 3> lo{}, hi{};
  Eigen::Vector3d normal;
  double offset = 0;
};

bool boxes_apart(const FaceInGrid& f, const FaceInGrid& g) {
  for (int d = 0; d < 3; ++d)
    if (f.box_hi(d) < g.box_lo(d) || g.box_hi(d) < f.box_lo(d)) return true;
  return false;
}

// Are f's corners strictly on one side of g's plane? Then no edge of either can pass through the
// other; three dot products instead of six segment tests. The margin leaves near-coplanar pairs to
// the exact test.
bool one_side_of(const Vertices& vertices, const Faces& faces, Eigen::Index f, const FaceInGrid& g, double cell) {
  const double margin = 1e-12 * g.normal.norm() * cell;
  int above = 0, below = 0;
  for (int i = 0; i < 3; ++i) {
    const double* p = vertices.data() + 3 * faces(f, i);
    const double side = g.normal.x() * p[0] + g.normal.y() * p[1] + g.normal.z() * p[2] - g.offset;
    above += side > margin;
    below += side < -margin;
  }
  return above == 3 || below == 3;
}

// Does an edge of f pass through g?
bool edge_crosses(const Vertices& vertices, const Faces& faces, Eigen::Index f, Eigen::Index g) {
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d p = vertices.row(faces(f, i)), q = vertices.row(faces(f, (i + 1) % 3));
    if (segment_hits_triangle(p, q, vertices.row(faces(g, 0)), vertices.row(faces(g, 1)), vertices.row(faces(g, 2))))
      return true;
  }
  return false;
}

}  // namespace

std::vector<std::pair<std::int32_t, std::int32_t>> self_intersections(const Vertices& vertices, const Faces& faces,
                                                                      std::size_t max_pairs) {
  std::vector<std::pair<std::int32_t, std::int32_t>> hits;
  const Eigen::Index nf = faces.rows();
  if (nf == 0) return hits;
  // Grid cell: about twice the mean face extent, so most faces touch a few cells.
  const Eigen::Vector3d lo = vertices.colwise().minCoeff().transpose(), hi = vertices.colwise().maxCoeff().transpose();
  std::vector<FaceInGrid> in_grid(static_cast<size_t>(nf));
  double mean_extent = 0;
  for (Eigen::Index f = 0; f < nf; ++f) {
    const Eigen::Vector3d a = vertices.row(faces(f, 0)), b = vertices.row(faces(f, 1)), c = vertices.row(faces(f, 2));
    FaceInGrid& g = in_grid[static_cast<size_t>(f)];
    g.box_lo = a.cwiseMin(b).cwiseMin(c), g.box_hi = a.cwiseMax(b).cwiseMax(c);
    g.normal = (b - a).cross(c - a);
    g.offset = g.normal.dot(a);
    mean_extent += (g.box_hi - g.box_lo).maxCoeff();
  }
  const double cell = std::max(1e-6, 2 * mean_extent / static_cast<double>(nf));
  const Eigen::Vector3i dims = (((hi - lo) / cell).array().floor().cast<int>() + 1).matrix();
  auto key = [&](int x, int y, int z) { return (static_cast<std::int64_t>(x) * dims.y() + y) * dims.z() + z; };

  // Every (cell, face) the face's box touches, sorted by cell: each cell's faces are one run.
  std::vector<std::pair<std::int64_t, std::int32_t>> cell_faces;
  for (Eigen::Index f = 0; f < nf; ++f) {
    FaceInGrid& g = in_grid[static_cast<size_t>(f)];
    for (int d = 0; d < 3; ++d) {
      g.lo[static_cast<size_t>(d)] = static_cast<int>(std::floor((g.box_lo(d) - lo(d)) / cell));
      g.hi[static_cast<size_t>(d)] = static_cast<int>(std::floor((g.box_hi(d) - lo(d)) / cell));
    }
    for (int x = g.lo[0]; x <= g.hi[0]; ++x)
      for (int y = g.lo[1]; y <= g.hi[1]; ++y)
        for (int z = g.lo[2]; z <= g.hi[2]; ++z) cell_faces.emplace_back(key(x, y, z), static_cast<std::int32_t>(f));
  }
  std::sort(cell_faces.begin(), cell_faces.end());

  // A pair is tested once, in the first cell both boxes touch (the corner of their boxes'
  // overlap), so no pair is tested twice however many cells they share.
  auto first_shared_cell = [&](const FaceInGrid& f, const FaceInGrid& g) {
    return key(std::max(f.lo[0], g.lo[0]), std::max(f.lo[1], g.lo[1]), std::max(f.lo[2], g.lo[2]));
  };
  auto share_vertex = [&](std::int32_t f, std::int32_t g) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (faces(f, i) == faces(g, j)) return true;
    return false;
  };
  for (size_t run = 0; run < cell_faces.size() && hits.size() < max_pairs;) {
    size_t end = run;
    while (end < cell_faces.size() && cell_faces[end].first == cell_faces[run].first) ++end;
    for (size_t i = run; i < end && hits.size() < max_pairs; ++i)
      for (size_t j = i + 1; j < end && hits.size() < max_pairs; ++j) {
        const std::int32_t f = cell_faces[i].second, g = cell_faces[j].second;
        const FaceInGrid &in_f = in_grid[static_cast<size_t>(f)], &in_g = in_grid[static_cast<size_t>(g)];
        if (first_shared_cell(in_f, in_g) != cell_faces[run].first || boxes_apart(in_f, in_g) || share_vertex(f, g)) continue;
        if (one_side_of(vertices, faces, f, in_g, cell) || one_side_of(vertices, faces, g, in_f, cell)) continue;
        if (edge_crosses(vertices, faces, f, g) || edge_crosses(vertices, faces, g, f)) hits.emplace_back(f, g);
      }
    run = end;
  }
  return hits;
}

Eigen::VectorXd uv_signed_areas(const UvCoordinates& uv, const Faces& uv_faces) {
  Eigen::VectorXd area(uv_faces.rows());
  for (Eigen::Index f = 0; f < uv_faces.rows(); ++f) {
    const Eigen::Vector2d a = uv.row(uv_faces(f, 0)), b = uv.row(uv_faces(f, 1)), c = uv.row(uv_faces(f, 2));
    area(f) = 0.5 * ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
  }
  return area;
}

namespace {

// Do the interiors of two non-degenerate triangles overlap by more than `tolerance`? Separating
// axis test: two convex polygons are disjoint or only touch iff some edge normal of either
// separates their projections (a gap ≥ −tolerance counts as separated).
bool triangles_overlap(const std::array<Eigen::Vector2d, 3>& p, const std::array<Eigen::Vector2d, 3>& q,
                       double tolerance) {
  auto separated_by_edges_of = [&](const std::array<Eigen::Vector2d, 3>& s, const std::array<Eigen::Vector2d, 3>& t) {
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector2d e = s[static_cast<size_t>((i + 1) % 3)] - s[static_cast<size_t>(i)];
      const double len = e.norm();
      if (len == 0) continue;
      const Eigen::Vector2d n(-e.y() / len, e.x() / len);
      double s0 = 1e300, s1 = -1e300, t0 = 1e300, t1 = -1e300;
      for (int k = 0; k < 3; ++k) {
        const double a = n.dot(s[static_cast<size_t>(k)]), b = n.dot(t[static_cast<size_t>(k)]);
        s0 = std::min(s0, a), s1 = std::max(s1, a), t0 = std::min(t0, b), t1 = std::max(t1, b);
      }
      if (s1 <= t0 + tolerance || t1 <= s0 + tolerance) return true;
    }
    return false;
  };
  return !separated_by_edges_of(p, q) && !separated_by_edges_of(q, p);
}

}  // namespace

std::vector<std::pair<std::int32_t, std::int32_t>> uv_overlaps(const UvCoordinates& uv, const Faces& uv_faces,
                                                               double tolerance, std::size_t max_pairs) {
  std::vector<std::pair<std::int32_t, std::int32_t>> hits;
  const Eigen::Index nf = uv_faces.rows();
  if (nf == 0 || uv.rows() == 0) return hits;
  const Eigen::VectorXd area = uv_signed_areas(uv, uv_faces);
  auto corners = [&](Eigen::Index f) {
    return std::array<Eigen::Vector2d, 3>{uv.row(uv_faces(f, 0)).transpose(), uv.row(uv_faces(f, 1)).transpose(),
                                          uv.row(uv_faces(f, 2)).transpose()};
  };
  // Grid cell: about twice the mean triangle extent; at most 2048 cells a side.
  const Eigen::Vector2d lo = uv.colwise().minCoeff().transpose(), hi = uv.colwise().maxCoeff().transpose();
  double mean_extent = 0;
  for (Eigen::Index f = 0; f < nf; ++f) {
    const auto c = corners(f);
    mean_extent += (c[0].cwiseMax(c[1]).cwiseMax(c[2]) - c[0].cwiseMin(c[1]).cwiseMin(c[2])).maxCoeff();
  }
  const double cell = std::max({1e-12, 2 * mean_extent / static_cast<double>(nf), (hi - lo).maxCoeff() / 2048});
  const std::int64_t ny = static_cast<std::int64_t>(std::floor((hi.y() - lo.y()) / cell)) + 1;
  auto cells_of = [&](Eigen::Index f, auto&& visit) {
    const auto c = corners(f);
    const Eigen::Vector2d b0 = c[0].cwiseMin(c[1]).cwiseMin(c[2]), b1 = c[0].cwiseMax(c[1]).cwiseMax(c[2]);
    const auto x0 = static_cast<std::int64_t>(std::floor((b0.x() - lo.x()) / cell)),
               x1 = static_cast<std::int64_t>(std::floor((b1.x() - lo.x()) / cell)),
               y0 = static_cast<std::int64_t>(std::floor((b0.y() - lo.y()) / cell)),
               y1 = static_cast<std::int64_t>(std::floor((b1.y() - lo.y()) / cell));
    for (std::int64_t x = x0; x <= x1; ++x)
      for (std::int64_t y = y0; y <= y1; ++y) visit(x * ny + y);
  };
  const double degenerate = 1e-18;
  std::unordered_map<std::int64_t, std::vector<std::int32_t>> grid;
  for (Eigen::Index f = 0; f < nf; ++f)
    if (std::abs(area(f)) > degenerate) cells_of(f, [&](std::int64_t k) { grid[k].push_back(static_cast<std::int32_t>(f)); });
  std::vector<std::int32_t> seen_stamp(static_cast<size_t>(nf), -1);
  for (Eigen::Index f = 0; f < nf && hits.size() < max_pairs; ++f) {
    if (std::abs(area(f)) <= degenerate) continue;
    const auto p = corners(f);
    cells_of(f, [&](std::int64_t k) {
      for (std::int32_t g : grid[k]) {
        if (g <= f || seen_stamp[static_cast<size_t>(g)] == f || hits.size() >= max_pairs) continue;
        seen_stamp[static_cast<size_t>(g)] = static_cast<std::int32_t>(f);
        if (triangles_overlap(p, corners(g), tolerance)) hits.emplace_back(static_cast<std::int32_t>(f), g);
      }
    });
  }
  return hits;
}

}  // namespace caliper
