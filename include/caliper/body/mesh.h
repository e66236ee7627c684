// Triangle meshes: vertex positions and faces, the topology every body of a model shares.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

namespace caliper {

using Vertices = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;      // N×3, metres
using Faces = Eigen::Matrix<std::int32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;   // F×3, counter-clockwise seen from outside

struct Mesh {
  Vertices vertices;
  Faces faces;
};

// Per-vertex unit normals, area-weighted average of the incident face normals.  N×3.
Vertices vertex_normals(const Vertices& vertices, const Faces& faces);

// Topology checks used by loaders and tests.
struct MeshCheck {
  bool closed = false;                 // every edge has exactly two incident faces
  bool manifold = false;               // closed and every vertex's fan is a single disc
  bool consistently_oriented = false;  // every edge is traversed once in each direction
  std::int64_t boundary_edges = 0;
  std::int64_t nonmanifold_edges = 0;
  std::int64_t unused_vertices = 0;
  std::int64_t degenerate_faces = 0;   // faces with a repeated vertex index
};
MeshCheck check_mesh(const Faces& faces, std::int64_t vertex_count);

// Pairs of faces that cross each other (an edge of one passes through the other), ignoring
// pairs that share a vertex. Stops after `max_pairs`. A uniform grid over face bounding boxes
// keeps it near-linear: ~20k faces take tens of milliseconds.
std::vector<std::pair<std::int32_t, std::int32_t>> self_intersections(const Vertices& vertices, const Faces& faces,
                                                                      std::size_t max_pairs = 100);

}  // namespace caliper
