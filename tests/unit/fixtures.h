// Small hand-built meshes and models with known answers, shared by the unit tests.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

#include "caliper/caliper.h"

namespace caliper::test {

// The caliper::Error that f throws; a test failure (and an empty error) when it throws none.
template <class F>
Error catch_error(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  ADD_FAILURE() << "no caliper::Error thrown";
  return Error(ErrorKind::Unsupported, "none");
}

// The kind of the caliper::Error that f throws (a test failure when it throws none), its message
// and field copied out when asked for.
template <class F>
ErrorKind kind_of(F&& f, std::string* message = nullptr, std::string* field = nullptr) {
  const Error e = catch_error(std::forward<F>(f));
  if (message) *message = e.what();
  if (field) *field = e.field();
  return e.kind();
}

// Axis-aligned unit cube [0,1]³, 12 outward triangles: volume exactly 1.
inline Mesh unit_cube() {
  Mesh m;
  m.vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.vertices.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  m.faces.resize(12, 3);
  m.faces << 0, 2, 1, 1, 2, 3,  // z = 0 (normal −z)
      4, 5, 6, 5, 7, 6,         // z = 1
      0, 1, 4, 1, 5, 4,         // y = 0
      2, 6, 3, 3, 6, 7,         // y = 1
      0, 4, 2, 2, 4, 6,         // x = 0
      1, 3, 5, 3, 7, 5;         // x = 1
  return m;
}

// A closed prism along +Y: `sides`-gon of circumradius r, from y = 0 to y = h, with `rings`
// horizontal rings of vertices and a centre vertex on each cap. Ring r, corner k is vertex
// r·sides + k; the bottom centre is rings·sides, the top centre rings·sides + 1.
inline Mesh prism(int sides, int rings, double r, double h) {
  Mesh m;
  m.vertices.resize(rings * sides + 2, 3);
  for (int ring = 0; ring < rings; ++ring)
    for (int k = 0; k < sides; ++k) {
      const double a = 2 * M_PI * k / sides;
      m.vertices.row(ring * sides + k) << r * std::cos(a), h * ring / (rings - 1), r * std::sin(a);
    }
  const int bottom = rings * sides, top = bottom + 1;
  m.vertices.row(bottom) << 0, 0, 0;
  m.vertices.row(top) << 0, h, 0;
  std::vector<Eigen::Vector3i> f;
  for (int ring = 0; ring + 1 < rings; ++ring)
    for (int k = 0; k < sides; ++k) {
      const int a = ring * sides + k, b = ring * sides + (k + 1) % sides, c = a + sides, d = b + sides;
      // Outward: angle grows from +X towards +Z, so (a, c, b) faces away from the axis.
      f.push_back({a, c, b});
      f.push_back({b, c, d});
    }
  for (int k = 0; k < sides; ++k) {
    f.push_back({bottom, k, (k + 1) % sides});
    f.push_back({top, (rings - 1) * sides + (k + 1) % sides, (rings - 1) * sides + k});
  }
  m.faces.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (size_t i = 0; i < f.size(); ++i) m.faces.row(static_cast<Eigen::Index>(i)) = f[i].transpose();
  return m;
}

// A toy body model on a prism: β0 stretches it vertically (+10 cm per SD), β1 widens it
// (+2 cm radius per SD), β2 stretches it vertically and narrows it. Every coordinate is linear
// in β, so heights are exactly linear and the regressors must reproduce them exactly.
inline BodyModel toy_model(int sides = 24, int rings = 9) {
  const double r = 0.15, h = 1.7;
  Mesh m = prism(sides, rings, r, h);
  BodyModelData d;
  d.name = "toy";
  d.sex = Sex::Neutral;
  d.template_vertices = m.vertices;
  d.faces = m.faces;
  const Eigen::Index n = m.vertices.rows();
  d.shape_directions = Eigen::MatrixXd::Zero(3 * n, 3);
  for (Eigen::Index v = 0; v < n; ++v) {
    d.shape_directions(3 * v + 1, 0) = m.vertices(v, 1) / h * 0.10;
    d.shape_directions(3 * v + 0, 1) = m.vertices(v, 0) / r * 0.02;
    d.shape_directions(3 * v + 2, 1) = m.vertices(v, 2) / r * 0.02;
    d.shape_directions(3 * v + 1, 2) = m.vertices(v, 1) / h * 0.05;
    d.shape_directions(3 * v + 0, 2) = -m.vertices(v, 0) / r * 0.01;
    d.shape_directions(3 * v + 2, 2) = -m.vertices(v, 2) / r * 0.01;
  }
  d.joint_names = smpl_joint_names();
  d.parents = smpl_parents();
  // Joints spread along the axis; each regressed from the ring at its height.
  const int joints = 24;
  std::vector<Eigen::Triplet<double>> jr, sw;
  for (int j = 0; j < joints; ++j) {
    const int ring = j * (rings - 1) / (joints - 1);
    for (int k = 0; k < sides; ++k) jr.emplace_back(j, ring * sides + k, 1.0 / sides);
  }
  for (Eigen::Index v = 0; v < n; ++v) {
    const int ring = v < rings * sides ? static_cast<int>(v / sides) : (v == rings * sides ? 0 : rings - 1);
    const int j = ring * (joints - 1) / (rings - 1);
    sw.emplace_back(static_cast<int>(v), j, 1.0);
  }
  d.joint_regressor.resize(joints, n);
  d.joint_regressor.setFromTriplets(jr.begin(), jr.end());
  d.skin_weights.resize(n, joints);
  d.skin_weights.setFromTriplets(sw.begin(), sw.end());
  const int top = rings * sides + 1, mid = (rings / 2) * sides;
  d.landmarks = {{"vertex", top}, {"waist_side", mid}, {"crotch", 2 * sides}, {"low", sides}};
  d.measurements = {
      {"stature", MeasurementKind::Height, {"vertex"}, Axis::Y, "top"},
      {"crotch_height", MeasurementKind::Height, {"crotch"}, Axis::Y, "ring 2"},
      {"waist_circumference", MeasurementKind::Circumference, {"waist_side"}, Axis::Y, "mid ring"},
      {"waist_breadth", MeasurementKind::Breadth, {"waist_side"}, Axis::Y, "mid ring"},
      {"waist_depth", MeasurementKind::Depth, {"waist_side"}, Axis::Y, "mid ring"},
      {"span", MeasurementKind::Length, {"low", "crotch", "vertex"}, Axis::Y, "polyline"},
      {"weight", MeasurementKind::Weight, {}, Axis::Y, "volume"},
  };
  d.weight_from_volume = {1000.0, 0.0};
  return BodyModel(std::move(d));
}

}  // namespace caliper::test
