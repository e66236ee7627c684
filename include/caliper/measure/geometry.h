// Geometry behind the virtual measurements (paper §3.4.2): volume by signed tetrahedra,
// plane sections, and the convex hull a tape measure follows.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "caliper/body/mesh.h"

namespace caliper {

// Signed volume of a closed, outward-oriented mesh: Σ over faces of (a · (b × c)) / 6.  m³.
double signed_volume(const Vertices& vertices, const Faces& faces);
// The same, and its gradient in the vertices (3N, x y z per vertex): a face adds (b × c)/6 to
// ∂V/∂a, and cyclically. One pass over the faces (the estimator runs it at every step).
double signed_volume(const Vertices& vertices, const Faces& faces, Eigen::VectorXd& gradient);

// Where a plane crosses the mesh edge (a, b): q = v_a + t·(v_b − v_a). Keeping the edge lets a
// measurement on the section be differentiated with respect to the vertices (map_estimator).
struct SectionPoint {
  Eigen::Vector3d q;
  int a = 0, b = 0;
  double t = 0;
};

// Closed loops where the plane through `point` with unit `normal` cuts the mesh, as crossings.
// Each loop is a list of points (not repeated at the end).
std::vector<std::vector<SectionPoint>> plane_section_points(const Vertices& vertices, const Faces& faces,
                                                            const Eigen::Vector3d& point,
                                                            const Eigen::Vector3d& normal);
// The same as 3D positions only.
std::vector<std::vector<Eigen::Vector3d>> plane_section(const Vertices& vertices, const Faces& faces,
                                                        const Eigen::Vector3d& point,
                                                        const Eigen::Vector3d& normal);

// Indices of the 2D convex hull's corners, counter-clockwise (Andrew's monotone chain).
std::vector<size_t> convex_hull(const std::vector<Eigen::Vector2d>& points);
// Perimeter of the 2D convex hull of points.
double convex_hull_perimeter(const std::vector<Eigen::Vector2d>& points);

}  // namespace caliper
