#include "caliper/body/body_model.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "caliper/errors.h"

namespace caliper {

WeightFromVolume WeightFromVolume::paper(Sex sex) {
  // Paper §3.4.2, fitted on CAESAR (kg, m³).
  switch (sex) {
    case Sex::Female: return {1001.44, -2.36};
    case Sex::Male: return {1056.44, -5.28};
    case Sex::Neutral: return {(1001.44 + 1056.44) / 2, (-2.36 - 5.28) / 2};
  }
  return {};
}

const std::vector<std::string>& smpl_joint_names() {
  static const std::vector<std::string> names = {
      "pelvis",     "left_hip",       "right_hip",      "spine1",     "left_knee",   "right_knee",
      "spine2",     "left_ankle",     "right_ankle",    "spine3",     "left_foot",   "right_foot",
      "neck",       "left_collar",    "right_collar",   "head",       "left_shoulder", "right_shoulder",
      "left_elbow", "right_elbow",    "left_wrist",     "right_wrist", "left_hand",  "right_hand"};
  return names;
}

const std::vector<int>& smpl_parents() {
  static const std::vector<int> parents = {-1, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8,
                                           9, 9, 9, 12, 13, 14, 16, 17, 18, 19, 20, 21};
  return parents;
}

const std::vector<std::string>& finger_joint_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const char* side : {"left", "right"})
      for (const char* finger : {"index", "middle", "pinky", "ring", "thumb"})
        for (int k = 1; k <= 3; ++k) n.push_back(std::string(side) + "_" + finger + std::to_string(k));
    return n;
  }();
  return names;
}

const std::vector<std::string>& rig_joint_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n = smpl_joint_names();
    n.insert(n.end(), finger_joint_names().begin(), finger_joint_names().end());
    return n;
  }();
  return names;
}

const std::vector<int>& rig_parents() {
  static const std::vector<int> parents = [] {
    std::vector<int> p = smpl_parents();
    const int left_hand = 22, right_hand = 23, first = static_cast<int>(p.size());
    for (int k = 0; k < 30; ++k) p.push_back(k % 3 == 0 ? (k < 15 ? left_hand : right_hand) : first + k - 1);
    return p;
  }();
  return parents;
}

namespace {

[[noreturn]] void inconsistent(const std::string& field, const std::string& what) {
  throw Error(ErrorKind::Format, "body model: " + field + ": " + what, field);
}

bool all_finite(const Eigen::Ref<const Eigen::MatrixXd>& m) { return m.allFinite(); }

void validate_uvs(const BodyModelData& d) {
  const Eigen::Index u = d.uv_coordinates.rows(), f = d.uv_faces.rows();
  if (u == 0 && f == 0) return;  // no UV layout
  if (u == 0) inconsistent("uv_coordinates", "missing while uv_faces has " + std::to_string(f) + " rows");
  if (f == 0) inconsistent("uv_faces", "missing while uv_coordinates has " + std::to_string(u) + " rows");
  if (f != d.faces.rows())
    inconsistent("uv_faces", "has " + std::to_string(f) + " rows for " + std::to_string(d.faces.rows()) + " faces");
  if (d.uv_faces.minCoeff() < 0 || d.uv_faces.maxCoeff() >= u)
    inconsistent("uv_faces", "index out of range [0, " + std::to_string(u) + ")");
  if (!d.uv_coordinates.allFinite()) inconsistent("uv_coordinates", "contains NaN or infinity");
  if (d.uv_coordinates.minCoeff() < 0 || d.uv_coordinates.maxCoeff() > 1)
    inconsistent("uv_coordinates", "values must lie in [0, 1]");
}

void validate(const BodyModelData& d) {
  const Eigen::Index n = d.template_vertices.rows();
  if (n < 4) inconsistent("template_vertices", "needs at least 4 vertices, has " + std::to_string(n));
  if (!d.template_vertices.allFinite()) inconsistent("template_vertices", "contains NaN or infinity");
  if (d.faces.rows() < 4) inconsistent("faces", "needs at least 4 faces");
  if (d.faces.minCoeff() < 0 || d.faces.maxCoeff() >= n)
    inconsistent("faces", "vertex index out of range [0, " + std::to_string(n) + ")");
  if (d.shape_directions.rows() != 3 * n)
    inconsistent("shape_directions", "has " + std::to_string(d.shape_directions.rows()) +
                                         " rows, expected 3×" + std::to_string(n));
  if (!all_finite(d.shape_directions)) inconsistent("shape_directions", "contains NaN or infinity");
  const Eigen::Index j = static_cast<Eigen::Index>(d.joint_names.size());
  if (j < 1) inconsistent("joint_names", "no joints");
  if (static_cast<Eigen::Index>(d.parents.size()) != j)
    inconsistent("parents", "has " + std::to_string(d.parents.size()) + " entries for " + std::to_string(j) + " joints");
  for (Eigen::Index i = 0; i < j; ++i) {
    const int p = d.parents[static_cast<size_t>(i)];
    if (i == 0 ? p != -1 : (p < 0 || p >= i))
      inconsistent("parents", "joint " + std::to_string(i) + " has parent " + std::to_string(p) +
                                  " (the root must be joint 0 with parent -1; parents precede children)");
  }
  if (d.joint_regressor.rows() != j || d.joint_regressor.cols() != n)
    inconsistent("joint_regressor", "must be " + std::to_string(j) + "×" + std::to_string(n));
  if (d.skin_weights.rows() != n || d.skin_weights.cols() != j)
    inconsistent("skin_weights", "must be " + std::to_string(n) + "×" + std::to_string(j));
  for (Eigen::Index r = 0; r < j; ++r) {
    const double s = d.joint_regressor.row(r).sum();
    if (!std::isfinite(s) || std::abs(s - 1.0) > 1e-3)
      inconsistent("joint_regressor", "row " + std::to_string(r) + " sums to " + std::to_string(s) + ", expected 1");
  }
  for (Eigen::Index r = 0; r < n; ++r) {
    double s = 0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(d.skin_weights, r); it; ++it) {
      if (!std::isfinite(it.value()) || it.value() < -1e-6)
        inconsistent("skin_weights", "vertex " + std::to_string(r) + " has a negative or non-finite weight");
      s += it.value();
    }
    if (std::abs(s - 1.0) > 1e-3)
      inconsistent("skin_weights", "vertex " + std::to_string(r) + " weights sum to " + std::to_string(s) + ", expected 1");
  }
  for (const auto& [name, v] : d.landmarks)
    if (v < 0 || v >= n) inconsistent("landmarks", "landmark '" + name + "' has vertex " + std::to_string(v) + " out of range");
  for (const auto& m : d.measurements) {
    for (const auto& l : m.landmarks)
      if (!d.landmarks.count(l))
        inconsistent("measurements", "measurement '" + m.name + "' uses unknown landmark '" + l + "'");
    if (m.kind == MeasurementKind::FrontBreadth && m.plane_normal != Axis::Y)
      inconsistent("measurements", "measurement '" + m.name + "': a front breadth needs a horizontal section (plane_normal y)");
  }
  validate_uvs(d);
  if (!std::isfinite(d.weight_from_volume.a) || !std::isfinite(d.weight_from_volume.b) || d.weight_from_volume.a <= 0)
    inconsistent("weight_from_volume", "coefficients must be finite with a > 0");
}

UvSplitMesh split_at_uv_seams(const BodyModelData& d) {
  const size_t n = static_cast<size_t>(d.template_vertices.rows());
  UvSplitMesh out;
  out.source.resize(n);
  for (size_t v = 0; v < n; ++v) out.source[v] = v;
  out.uv.assign(n, {0.0, 0.0});
  out.faces = d.faces;
  if (d.uv_faces.rows() == 0) return out;
  const Faces& uv_faces = d.uv_faces;
  const UvCoordinates& uv = d.uv_coordinates;
  std::vector<std::int32_t> first_uv(n, -1);  // the UV each model vertex keeps
  // Each vertex's further UVs, with the output vertex written for each: only the seams' vertices
  // have any, so a short list per vertex.
  std::vector<std::vector<std::pair<std::int32_t, std::int32_t>>> copies(n);
  for (Eigen::Index f = 0; f < out.faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::int32_t v = d.faces(f, k), t = uv_faces(f, k);
      auto& kept = first_uv[static_cast<size_t>(v)];
      if (kept < 0) kept = t;
      if (kept == t) {
        out.uv[static_cast<size_t>(v)] = {uv(t, 0), uv(t, 1)};
        continue;
      }
      auto& mine = copies[static_cast<size_t>(v)];
      auto it = std::find_if(mine.begin(), mine.end(), [t](const auto& copy) { return copy.first == t; });
      if (it == mine.end()) {
        it = mine.insert(mine.end(), {t, static_cast<std::int32_t>(out.source.size())});
        out.source.push_back(static_cast<size_t>(v));
        out.uv.push_back({uv(t, 0), uv(t, 1)});
      }
      out.faces(f, k) = it->second;
    }
  return out;
}

}  // namespace

BodyModel::BodyModel(BodyModelData data) : data_(std::move(data)) {
  data_.joint_regressor.makeCompressed();
  data_.skin_weights.makeCompressed();
  validate(data_);
  shape_directions_f_ = data_.shape_directions.cast<float>();
  uv_split_ = split_at_uv_seams(data_);
}

int BodyModel::landmark(const std::string& name) const {
  auto it = data_.landmarks.find(name);
  if (it == data_.landmarks.end())
    throw Error(ErrorKind::Unsupported, "model '" + data_.name + "' has no landmark '" + name + "'", name);
  return it->second;
}

const MeasurementDefinition* BodyModel::find_measurement(const std::string& name) const {
  for (const auto& m : data_.measurements)
    if (m.name == name) return &m;
  return nullptr;
}

void BodyModel::rest_vertices(const Eigen::VectorXd& beta, Vertices& out) const {
  const Eigen::Index k = data_.shape_directions.cols();
  if (beta.size() > k)
    throw Error(ErrorKind::InvalidArgument,
                "beta has " + std::to_string(beta.size()) + " values; model '" + data_.name + "' has " +
                    std::to_string(k) + " shape directions", "beta");
  if (!beta.allFinite()) throw Error(ErrorKind::InvalidArgument, "beta contains NaN or infinity", "beta");
  out.resize(data_.template_vertices.rows(), 3);
  // Vertices is row-major N×3, so its storage is exactly the 3N vector the directions index.
  Eigen::Map<Eigen::VectorXd> flat(out.data(), out.size());
  flat = Eigen::Map<const Eigen::VectorXd>(data_.template_vertices.data(), data_.template_vertices.size());
  if (beta.size() > 0)
    flat += (shape_directions_f_.leftCols(beta.size()) * beta.cast<float>()).cast<double>();
}

Vertices BodyModel::rest_vertices(const Eigen::VectorXd& beta) const {
  Vertices v;
  rest_vertices(beta, v);
  return v;
}

Eigen::RowVectorXd BodyModel::shape_gradient(const Eigen::Ref<const Eigen::VectorXd>& vertex_gradient) const {
  if (vertex_gradient.size() != shape_directions_f_.rows())
    throw Error(ErrorKind::InvalidArgument, "vertex gradient size does not match the model", "vertex_gradient");
  return (vertex_gradient.cast<float>().transpose() * shape_directions_f_).cast<double>();
}

Eigen::MatrixX3d BodyModel::joints(const Vertices& rest) const {
  if (rest.rows() != data_.template_vertices.rows())
    throw Error(ErrorKind::InvalidArgument, "vertex count does not match the model", "vertices");
  return data_.joint_regressor * rest;
}

BodyModel BodyModel::supplied_by(ErrorOrigin origin) && {
  data_.supplied_by = origin;
  return std::move(*this);
}

BodyModel BodyModel::truncated(int k) const {
  if (k < 1 || k > shape_count())
    throw Error(ErrorKind::OutOfRange,
                "shape count must be in [1, " + std::to_string(shape_count()) + "], got " + std::to_string(k), "shapes");
  BodyModelData d = data_;
  d.shape_directions = data_.shape_directions.leftCols(k);
  return BodyModel(std::move(d));
}

}  // namespace caliper
