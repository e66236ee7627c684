// The built-in procedural body ("mannequin"): from ANSUR II body dimensions to a closed,
// fixed-topology triangle mesh in a T-pose, with landmarks, a 24-joint SMPL-style rig and
// skinning weights. Lofted horizontal rings (torso, legs, head) and rings across the arms,
// joined by hand-designed junctions (crotch, armpits, thumbs). Every body has the same
// vertices and faces, so a population of bodies can be analysed by PCA.
#pragma once
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <map>
#include <string>
#include <vector>

#include "caliper/body/body_model.h"
#include "caliper/body/mesh.h"
#include "caliper/vocabulary/definitions.h"

namespace caliper::mannequin {

// ANSUR II column names, lowercase (e.g. "stature", "crotchheight", "chestcircumference"), metres.
using Dimensions = std::map<std::string, double>;

// The ANSUR columns the generator reads, in a fixed order.
const std::vector<std::string>& input_columns();

// Typical adult dimensions per sex (ANSUR II development-subset means). Neutral = their average.
Dimensions typical_dimensions(Sex sex);
// Fills any dimension missing from `partial` from typical_dimensions scaled by stature (if
// `partial` has a stature), so the generator can be driven by a few values.
Dimensions complete_dimensions(const Dimensions& partial, Sex sex);

struct Topology {  // shared by every generated body
  Faces faces;     // F×3, counter-clockwise seen from outside (outward normals)
  int vertex_count = 0;
  std::map<std::string, int> landmarks;                          // name → vertex index
  Eigen::SparseMatrix<double, Eigen::RowMajor> joint_regressor;  // 24×N, rows sum to 1, ≥ 0
  Eigen::SparseMatrix<double, Eigen::RowMajor> skin_weights;     // N×24, rows sum to 1, ≥ 0, ≤ 4 nonzeros per row
};
const Topology& topology();  // built once (thread-safe static)

// The topology's UV layout (texture coordinates), unwrapped from `rest` (N×3 rest vertices of
// this topology, e.g. a model's mean body; metres). One atlas in [0, 1]², OBJ convention (v up),
// islands that do not overlap: torso + neck + head cut down the back; each leg with the top of its
// foot cut along the inner leg; each sole; each arm with its mitten hand cut under the arm; each
// thumb. Right-side islands are the mirror images of the left's. Deterministic. Throws
// Error(InvalidArgument) if `rest` does not have the topology's vertex count.
struct UvLayout {
  UvCoordinates coordinates;  // U×2
  Faces faces;                // F×3 (topology().faces' rows), indices into coordinates
};
UvLayout uv_layout(const Vertices& rest);

// Rest vertices N×3 in metres, T-pose, feet on y = 0, facing +Z. `sex` selects the female/male
// form (bust, hip and shoulder shape); geometry is otherwise driven by the dimensions (all of
// input_columns() must be present: use complete_dimensions). Throws Error(InvalidArgument),
// naming the dimension, for missing, NaN, non-positive or absurd values.
Vertices generate(const Dimensions& dims, Sex sex);

// The measurement definitions this topology supports (names from the measurement catalogue).
std::vector<MeasurementDefinition> measurement_definitions();

// The inputs each generated body reproduces when measured by Caliper's measurement code
// (heights/lengths/breadths/depths to 3 mm, circumferences to 1 %). Known exceptions, where an
// ANSUR subject's values are mutually infeasible for the body's construction, are documented
// in generator.cpp (e.g. a chest circumference beyond what its breadth and depth allow).
struct FidelityTarget {
  std::string measurement;   // definition name, e.g. "chest_circumference"
  std::string ansur_column;  // e.g. "chestcircumference"
  bool circumference = false;
};
std::vector<FidelityTarget> fidelity_targets();

}  // namespace caliper::mannequin
