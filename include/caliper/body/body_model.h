// The linear body model (paper §3.4.1; SMPL, Loper et al. 2015, without pose correctives):
//   rest vertices T(β) = T̄ + S·β,   joints J(β) = J_reg · T(β),
// a kinematic tree of named joints and linear-blend-skinning weights.
// A BodyModel is immutable once built and shared by every body made from it; a Body is the cheap
// per-person value (β and the vertices and joints it yields).
#pragma once
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "caliper/body/mesh.h"
#include "caliper/errors.h"
#include "caliper/vocabulary/definitions.h"
#include "caliper/vocabulary/sex.h"

namespace caliper {

// weight_kg = a · volume_m3 + b  (paper §3.4.2). The paper's fit on CAESAR is the default.
struct WeightFromVolume {
  double a = 1028.94;  // kg per m³
  double b = -3.82;    // kg
  static WeightFromVolume paper(Sex sex);  // female 1001.44/−2.36, male 1056.44/−5.28, neutral their mean
  double weight_kg(double volume_m3) const { return a * volume_m3 + b; }
};

// The 24 joints of SMPL, in SMPL's order.
const std::vector<std::string>& smpl_joint_names();
const std::vector<int>& smpl_parents();  // parent index per joint, −1 for the root (pelvis)
// SMPL-H's 30 finger joints in SMPL-H's order: left_index1…3, left_middle1…3, left_pinky1…3,
// left_ring1…3, left_thumb1…3, then the same for the right hand (1: knuckle, 3: last joint).
const std::vector<std::string>& finger_joint_names();
// The built-in body's rig: SMPL's 24 joints (names and order kept, so SMPL poses drive it)
// followed by the 30 finger joints. Each finger's first joint hangs from SMPL's hand joint, so a
// pose that bends left_hand curls the whole hand, and SMPL-H hand poses (relative to the wrist;
// they leave the hand joint at rest) drive each finger.
const std::vector<std::string>& rig_joint_names();
const std::vector<int>& rig_parents();

struct BodyModelData {
  std::string name;                    // e.g. "mannequin-female"
  Sex sex = Sex::Neutral;
  Vertices template_vertices;          // N×3 mean rest shape T̄, metres, T-pose, feet on y = 0
  Faces faces;                         // F×3
  Eigen::MatrixXd shape_directions;    // 3N×K, row 3v+c = coordinate c of vertex v; β ~ N(0, I)
  Eigen::SparseMatrix<double, Eigen::RowMajor> joint_regressor;  // J×N, rows sum to 1
  std::vector<std::string> joint_names;                           // J
  std::vector<int> parents;                                       // J, −1 for the root
  Eigen::SparseMatrix<double, Eigen::RowMajor> skin_weights;      // N×J, rows sum to 1
  std::map<std::string, int> landmarks;                           // name → vertex index
  std::vector<MeasurementDefinition> measurements;                // what this model can measure
  WeightFromVolume weight_from_volume;
  std::map<std::string, std::string> metadata;                    // licence, source, version…
  // Optional UV layout (texture coordinates) shared by every body of the model, OBJ-style: a
  // vertex on a seam has several UVs, so UV corners index their own array. Both empty = none.
  UvCoordinates uv_coordinates;  // U×2 in [0, 1], OBJ convention (v up; origin bottom-left)
  Faces uv_faces;                // F×3 indices into uv_coordinates, same corner order as `faces`
  // Whose file the model came from (load_model says; not stored in the file): what is read from
  // its contents later, such as its real → virtual maps, fails as that file's error.
  ErrorOrigin supplied_by = ErrorOrigin::Caller;
};

// The mesh with one UV per vertex, as GPU formats (glTF, VRM) need it: a vertex on a UV seam is
// written once per UV it has. Vertex v of this mesh is model vertex source[v] with UV uv[v].
struct UvSplitMesh {
  std::vector<size_t> source;
  std::vector<std::array<double, 2>> uv;  // OBJ convention; (0, 0) without a layout
  Faces faces;                            // F×3 into this mesh's vertices
};

class BodyModel {
 public:
  // Validates shapes, indices and sums; throws Error(Format) naming the array on inconsistency.
  explicit BodyModel(BodyModelData data);

  const BodyModelData& data() const { return data_; }
  const std::string& name() const { return data_.name; }
  Sex sex() const { return data_.sex; }
  int vertex_count() const { return static_cast<int>(data_.template_vertices.rows()); }
  int face_count() const { return static_cast<int>(data_.faces.rows()); }
  int joint_count() const { return static_cast<int>(data_.joint_names.size()); }
  int shape_count() const { return static_cast<int>(data_.shape_directions.cols()); }
  const Faces& faces() const { return data_.faces; }
  bool has_uvs() const { return data_.uv_faces.rows() > 0; }
  // Worked out once, when the model is built: it depends only on the faces and the UV layout,
  // and the .glb writer spent a tenth of its time redoing it per avatar (docs/performance.md).
  const UvSplitMesh& uv_split() const { return uv_split_; }

  // Landmark vertex index; throws Error(Unsupported) naming the landmark if the model lacks it.
  int landmark(const std::string& name) const;
  const MeasurementDefinition* find_measurement(const std::string& name) const;

  // Rest vertices T(β), N×3. β may be shorter than K (missing values are 0); longer throws.
  // S·β is evaluated in single precision (see shape_directions_f_); T̄ is added in double.
  Vertices rest_vertices(const Eigen::VectorXd& beta) const;
  void rest_vertices(const Eigen::VectorXd& beta, Vertices& out) const;  // no allocation when sized
  // gᵀS (1×K): how a function of the rest vertices changes with β, given its gradient g in the
  // vertices (3N, x y z per vertex). In single precision, as rest_vertices: each entry's error is
  // about 1e-7 of Σᵢ |gᵢ Sᵢₖ|, not of the entry itself.
  Eigen::RowVectorXd shape_gradient(const Eigen::Ref<const Eigen::VectorXd>& vertex_gradient) const;
  // Joints J(β), J×3, from rest vertices.
  Eigen::MatrixX3d joints(const Vertices& rest) const;

  // This model, marked as supplied by `origin` (BodyModelData::supplied_by); no copy, no re-check.
  BodyModel supplied_by(ErrorOrigin origin) &&;

  // A copy of this model keeping only the first k shape directions (1 ≤ k ≤ K).
  BodyModel truncated(int k) const;

 private:
  BodyModelData data_;
  // Single-precision copy of the shape directions for rest_vertices and shape_gradient: the
  // products are bound by memory traffic, and float halves it (error ≤ 1e-8 m, far below any
  // measurement's precision).
  Eigen::MatrixXf shape_directions_f_;
  UvSplitMesh uv_split_;
};

}  // namespace caliper
