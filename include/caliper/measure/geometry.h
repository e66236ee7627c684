// Geometry behind the virtual measurements (paper §3.4.2): volume by signed tetrahedra,
// plane sections, and the convex hull a tape measure follows.
#pragma once
#include <Eigen/Core>
#include <vector>

#include "caliper/body/mesh.h"

namespace caliper {

// Signed volume of a closed, outward-oriented mesh: Σ over faces of (a · (b × c)) / 6.  m³.
double signed_volume(const Vertices& vertices, const Faces& faces);

// Closed polylines where the plane through `point` with unit `normal` cuts the mesh.
// Each loop is a list of 3D points (not repeated at the end).
std::vector<std::vector<Eigen::Vector3d>> plane_section(const Vertices& vertices, const Faces& faces,
                                                        const Eigen::Vector3d& point,
                                                        const Eigen::Vector3d& normal);

// Perimeter of the 2D convex hull of points (Andrew's monotone chain).
double convex_hull_perimeter(const std::vector<Eigen::Vector2d>& points);

}  // namespace caliper
