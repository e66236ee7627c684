// Triangle meshes: vertex positions and faces, the topology every body of a model shares.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <utility>
#include <vector>

namespace caliper {

using Vertices = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;      // N×3, metres
using Faces = Eigen::Matrix<std::int32_t, Eigen::Dynamic, 3, Eigen::RowMajor>;   // F×3, counter-clockwise seen from outside
using UvCoordinates = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;  // U×2 texture coordinates (u, v)

struct Mesh {
  Vertices vertices;
  Faces faces;
};

// Per-vertex unit normals, N×3: the incident faces' normals weighted as Max (1999) proposes, each
// by the sine of its angle at the vertex over the lengths of its two edges there. That is exact for
// a vertex on a sphere however unevenly its neighbours lie. Area weighting tilted a vertex's normal
// toward its larger faces: where the body's rings change spacing (1.6 mm under the head's widest
// ring, 13 mm over it) the shading showed a band.
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
// keeps it near-linear: the 24k-face body takes about 20 ms (BM_SelfIntersections).
std::vector<std::pair<std::int32_t, std::int32_t>> self_intersections(const Vertices& vertices, const Faces& faces,
                                                                      std::size_t max_pairs = 100);

// Pairs of UV triangles whose interiors overlap (share a region of positive area), for a UV
// layout `uv` (U×2) and its triangles `uv_faces` (F×3 indices into `uv`). Triangles that only
// touch (a shared edge or vertex, or touching boundaries) do not count; overlaps thinner than
// `tolerance` (in UV units) are ignored. Degenerate (zero-area) triangles never overlap. Stops after
// `max_pairs`; pairs are (lower face index, higher). A uniform grid over the triangles' bounding
// boxes keeps it near-linear.
std::vector<std::pair<std::int32_t, std::int32_t>> uv_overlaps(const UvCoordinates& uv, const Faces& uv_faces,
                                                               double tolerance = 1e-9, std::size_t max_pairs = 100);

// Signed area of each UV triangle (F), positive when its corners run counter-clockwise in the
// (u, v) plane with v up (OBJ's convention).
Eigen::VectorXd uv_signed_areas(const UvCoordinates& uv, const Faces& uv_faces);

}  // namespace caliper
