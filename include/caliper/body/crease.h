// Creases: how sharply the surface folds between neighbouring faces. A smooth body has small
// dihedral angles everywhere except at features meant to be sharp (fingertips, the sole's rim,
// the nose); a band, a seam where a limb meets the torso, or a spike shows as an edge whose two
// faces meet at a large angle. Used to judge a body model's shape over a whole population.
#pragma once
#include <Eigen/SparseCore>
#include <cstdint>
#include <string>
#include <vector>

#include "caliper/body/body_model.h"
#include "caliper/body/mesh.h"

namespace caliper {

// One undirected edge shared by two faces and the angle between those faces' normals, degrees:
// 0 = the faces are coplanar, 90 = they meet at a right angle.
struct EdgeBend {
  std::int32_t a = 0, b = 0;  // vertex indices, a < b
  double degrees = 0;
};

// Every edge of a closed mesh with exactly two incident faces (boundary and non-manifold edges
// are skipped), in ascending (a, b) order. Degenerate faces count as bent 0°.
std::vector<EdgeBend> dihedral_angles(const Vertices& vertices, const Faces& faces);

// The body's regions, named by which joint moves each vertex most (its largest skin weight), so
// the report works for any model with SMPL-style joint names (and SMPL-H finger joints).
enum class BodyRegion { Torso, HeadNeck, Arms, Hands, Legs, Feet };
const char* to_string(BodyRegion region);
BodyRegion region_of_joint(const std::string& joint_name);  // unknown names: Torso
// Regions whose sharp edges are meant (fingertips and nails, the sole's rim, nose, lips, ears):
// hands, feet and head. The rest of the body should be smooth.
bool is_feature_region(BodyRegion region);

// Each vertex's region: that of the joint with its largest skin weight. N regions.
std::vector<BodyRegion> vertex_regions(const Eigen::SparseMatrix<double, Eigen::RowMajor>& skin_weights,
                                       const std::vector<std::string>& joint_names);

struct CreaseRegionSummary {
  BodyRegion region = BodyRegion::Torso;
  std::int64_t edges = 0;
  double max_degrees = 0;
  double p99_degrees = 0;  // 99th percentile of the region's edges
  EdgeBend worst;          // the edge with max_degrees
};

// Per region (in enum order, regions without edges left out): the largest and 99th-percentile
// dihedral angle of the edges whose two vertices both belong to it; an edge between two regions
// (a limb's junction with the torso) counts in the region farther from the torso, i.e. the limb.
// `regions` has one entry per vertex (vertex_regions).
std::vector<CreaseRegionSummary> crease_report(const Vertices& vertices, const Faces& faces,
                                               const std::vector<BodyRegion>& regions);
// The same for rest vertices (N×3) of `model`, regions from its skin weights.
std::vector<CreaseRegionSummary> crease_report(const BodyModel& model, const Vertices& rest);

// The largest dihedral angle over the regions that should be smooth (not is_feature_region).
double smooth_region_max_crease(const std::vector<CreaseRegionSummary>& report);

}  // namespace caliper
