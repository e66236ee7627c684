// UV layouts: the overlap checker on tiny triangles with known answers, the model's validation of
// its UV arrays, and the built-in body's layout (in [0, 1], no overlaps, counter-clockwise, one
// island per part, lengths kept roughly, deterministic) on the committed models and from the
// generator directly.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cstring>
#include <functional>
#include <numeric>

#include "caliper/caliper.h"
#include "caliper/mannequin/generator.h"
#include "fixtures.h"

using namespace caliper;

using caliper::test::catch_error;

namespace {

UvCoordinates uvs(std::initializer_list<std::array<double, 2>> points) {
  UvCoordinates uv(static_cast<Eigen::Index>(points.size()), 2);
  Eigen::Index i = 0;
  for (const auto& p : points) uv.row(i++) << p[0], p[1];
  return uv;
}

Faces tris(std::initializer_list<std::array<int, 3>> faces) {
  Faces f(static_cast<Eigen::Index>(faces.size()), 3);
  Eigen::Index i = 0;
  for (const auto& t : faces) f.row(i++) << t[0], t[1], t[2];
  return f;
}

using Pairs = std::vector<std::pair<std::int32_t, std::int32_t>>;

// A regular n×n grid of the unit square, two triangles per cell, counter-clockwise.
void grid(int n, UvCoordinates& uv, Faces& faces) {
  uv.resize((n + 1) * (n + 1), 2);
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) uv.row(y * (n + 1) + x) << static_cast<double>(x) / n, static_cast<double>(y) / n;
  faces.resize(2 * n * n, 3);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const int a = y * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
      faces.row(2 * (y * n + x)) << a, b, d;
      faces.row(2 * (y * n + x) + 1) << a, d, c;
    }
}

}  // namespace

// ---- the checker on cases with known answers ---------------------------------------------------

TEST(UvOverlaps, OverlappingTrianglesAreFound) {
  // Two triangles crossing like a star of David's halves.
  const UvCoordinates uv = uvs({{0.1, 0.1}, {0.5, 0.1}, {0.3, 0.5}, {0.1, 0.4}, {0.5, 0.4}, {0.3, 0.0}});
  EXPECT_EQ(uv_overlaps(uv, tris({{0, 1, 2}, {3, 5, 4}})), (Pairs{{0, 1}}));
  // One inside the other (no edges cross): still an overlap.
  const UvCoordinates nested = uvs({{0, 0}, {1, 0}, {0, 1}, {0.1, 0.1}, {0.2, 0.1}, {0.1, 0.2}});
  EXPECT_EQ(uv_overlaps(nested, tris({{0, 1, 2}, {3, 4, 5}})), (Pairs{{0, 1}}));
  // The same triangle twice, and a triangle folded back over its neighbour across a shared edge.
  EXPECT_EQ(uv_overlaps(nested, tris({{0, 1, 2}, {0, 1, 2}})), (Pairs{{0, 1}}));
  const UvCoordinates folded = uvs({{0, 0}, {1, 0}, {0.5, 1}, {0.5, 0.5}});
  EXPECT_EQ(uv_overlaps(folded, tris({{0, 1, 2}, {1, 0, 3}})), (Pairs{{0, 1}}));
  // Clockwise triangles overlap just the same.
  EXPECT_EQ(uv_overlaps(nested, tris({{0, 2, 1}, {3, 5, 4}})), (Pairs{{0, 1}}));
}

TEST(UvOverlaps, TouchingIsNotOverlapping) {
  // Sharing an edge (the two halves of a square), a vertex, or touching along part of an edge
  // without sharing vertices.
  const UvCoordinates square = uvs({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
  EXPECT_TRUE(uv_overlaps(square, tris({{0, 1, 2}, {0, 2, 3}})).empty());
  const UvCoordinates bow = uvs({{0, 0}, {1, 0}, {0.5, 0.5}, {1, 1}, {0, 1}});
  EXPECT_TRUE(uv_overlaps(bow, tris({{0, 1, 2}, {2, 3, 4}})).empty());
  const UvCoordinates stacked = uvs({{0, 0}, {1, 0}, {0.5, 0.5}, {0.25, 0}, {0.75, 0}, {0.5, -0.5}});
  EXPECT_TRUE(uv_overlaps(stacked, tris({{0, 1, 2}, {3, 5, 4}})).empty());
}

TEST(UvOverlaps, DisjointAndDegenerateTrianglesAreNot) {
  const UvCoordinates uv = uvs({{0, 0}, {0.2, 0}, {0, 0.2}, {0.5, 0.5}, {0.7, 0.5}, {0.5, 0.7}});
  EXPECT_TRUE(uv_overlaps(uv, tris({{0, 1, 2}, {3, 4, 5}})).empty());
  // A zero-area triangle lying across another has no interior to overlap with.
  const UvCoordinates line = uvs({{0, 0}, {1, 0}, {0, 1}, {-1, 0.2}, {2, 0.2}, {0.5, 0.2}});
  EXPECT_TRUE(uv_overlaps(line, tris({{0, 1, 2}, {3, 4, 5}})).empty());
  // Empty input.
  EXPECT_TRUE(uv_overlaps(UvCoordinates(), Faces()).empty());
}

TEST(UvOverlaps, TinyOverlapsBelowTheToleranceAreIgnored) {
  // Two squares' halves overlapping by 1e-6 in u.
  const UvCoordinates uv = uvs({{0, 0}, {0.5 + 1e-6, 0}, {0, 1}, {0.5, 0}, {1, 0}, {0.5, 1}});
  const Faces f = tris({{0, 1, 2}, {3, 4, 5}});
  EXPECT_EQ(uv_overlaps(uv, f, 1e-9).size(), 1u);
  EXPECT_TRUE(uv_overlaps(uv, f, 1e-5).empty());
}

TEST(UvOverlaps, GridFindsExactlyTheFoldedCells) {
  UvCoordinates uv;
  Faces faces;
  grid(60, uv, faces);  // 7,200 triangles
  EXPECT_TRUE(uv_overlaps(uv, faces).empty());
  EXPECT_TRUE((uv_signed_areas(uv, faces).array() > 0).all());
  // Push one interior vertex across its right-hand neighbour: the cells around it fold.
  const int n = 60, v = 30 * (n + 1) + 30;
  uv(v, 0) += 1.5 / n;
  const Pairs hits = uv_overlaps(uv, faces, 1e-9, 1000);
  EXPECT_FALSE(hits.empty());
  for (auto [a, b] : hits) {  // every pair involves a triangle using the moved vertex
    const bool a_uses = (faces.row(a).array() == v).any(), b_uses = (faces.row(b).array() == v).any();
    EXPECT_TRUE(a_uses || b_uses) << a << " " << b;
  }
  // The limit on pairs is honoured.
  EXPECT_EQ(uv_overlaps(uv, faces, 1e-9, 1).size(), 1u);
}

TEST(UvSignedAreas, CounterClockwiseIsPositive) {
  const UvCoordinates uv = uvs({{0, 0}, {1, 0}, {0, 1}});
  const Eigen::VectorXd a = uv_signed_areas(uv, tris({{0, 1, 2}, {0, 2, 1}, {0, 0, 1}}));
  EXPECT_DOUBLE_EQ(a(0), 0.5);
  EXPECT_DOUBLE_EQ(a(1), -0.5);
  EXPECT_DOUBLE_EQ(a(2), 0.0);
}

// ---- the model's validation of its UV arrays -------------------------------------------------

TEST(BodyModelUvs, ValidatedLikeTheOtherArrays) {
  const BodyModelData base = test::toy_model().data();
  const Eigen::Index f = base.faces.rows();
  auto with = [&](UvCoordinates uv, Faces uv_faces) {
    BodyModelData d = base;
    d.uv_coordinates = std::move(uv);
    d.uv_faces = std::move(uv_faces);
    return d;
  };
  // Valid: one UV per face corner, all at distinct points of the unit square.
  UvCoordinates uv(3 * f, 2);
  Faces uv_faces(f, 3);
  for (Eigen::Index i = 0; i < 3 * f; ++i) uv.row(i) << static_cast<double>(i) / (3 * f), 0.5;
  for (Eigen::Index i = 0; i < f; ++i) uv_faces.row(i) << 3 * i, 3 * i + 1, 3 * i + 2;
  EXPECT_TRUE(BodyModel(with(uv, uv_faces)).has_uvs());
  EXPECT_FALSE(BodyModel(base).has_uvs());

  auto field_of = [&](BodyModelData d) {
    const Error e = catch_error([&] { BodyModel m(std::move(d)); });
    EXPECT_EQ(e.kind(), ErrorKind::Format) << e.what();
    return e.field();
  };
  EXPECT_EQ(field_of(with(uv, Faces())), "uv_faces");             // one without the other
  EXPECT_EQ(field_of(with(UvCoordinates(), uv_faces)), "uv_coordinates");
  EXPECT_EQ(field_of(with(uv, uv_faces.topRows(f - 1))), "uv_faces");  // a row per face
  Faces bad = uv_faces;
  bad(3, 1) = static_cast<std::int32_t>(3 * f);  // one past the last UV
  EXPECT_EQ(field_of(with(uv, bad)), "uv_faces");
  bad(3, 1) = -1;
  EXPECT_EQ(field_of(with(uv, bad)), "uv_faces");
  UvCoordinates outside = uv;
  outside(2, 1) = 1.0 + 1e-9;
  EXPECT_EQ(field_of(with(outside, uv_faces)), "uv_coordinates");
  outside(2, 1) = std::nan("");
  EXPECT_EQ(field_of(with(outside, uv_faces)), "uv_coordinates");
  // Truncating a model keeps its layout.
  EXPECT_TRUE(BodyModel(with(uv, uv_faces)).truncated(1).has_uvs());
}

// ---- the built-in body's layout ----------------------------------------------------------------

namespace {

// Islands: faces connected through shared UV indices (so a seam separates them).
std::vector<int> uv_islands(const Faces& uv_faces, Eigen::Index uv_count, int* count) {
  std::vector<int> parent(static_cast<size_t>(uv_count));
  std::iota(parent.begin(), parent.end(), 0);
  std::function<int(int)> find = [&](int x) { return parent[static_cast<size_t>(x)] == x ? x : parent[static_cast<size_t>(x)] = find(parent[static_cast<size_t>(x)]); };
  for (Eigen::Index f = 0; f < uv_faces.rows(); ++f)
    for (int k = 1; k < 3; ++k) parent[static_cast<size_t>(find(uv_faces(f, k)))] = find(uv_faces(f, 0));
  std::map<int, int> label;
  std::vector<int> island(static_cast<size_t>(uv_faces.rows()));
  for (Eigen::Index f = 0; f < uv_faces.rows(); ++f)
    island[static_cast<size_t>(f)] = label.try_emplace(find(uv_faces(f, 0)), static_cast<int>(label.size())).first->second;
  *count = static_cast<int>(label.size());
  return island;
}

// Per face: the singular values of the map from the 3D triangle to its UV triangle, divided by
// the layout's overall scale (UV area / surface area, square-rooted): 1 and 1 = no distortion.
struct Distortion {
  double stretch_p95 = 0;      // 95th percentile (by surface area) of σ_max / σ_min
  double area_ratio_p05 = 0;   // 5th and 95th percentiles of σ_max · σ_min
  double area_ratio_p95 = 0;
};

Distortion distortion(const Vertices& v, const Faces& faces, const UvCoordinates& uv, const Faces& uv_faces) {
  const Eigen::VectorXd uv_area = uv_signed_areas(uv, uv_faces);
  std::vector<double> area3(static_cast<size_t>(faces.rows()));
  double total3 = 0, total_uv = 0;
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d a = v.row(faces(f, 0)), b = v.row(faces(f, 1)), c = v.row(faces(f, 2));
    area3[static_cast<size_t>(f)] = 0.5 * (b - a).cross(c - a).norm();
    total3 += area3[static_cast<size_t>(f)];
    total_uv += uv_area(f);
  }
  const double scale = std::sqrt(total_uv / total3);
  std::vector<std::array<double, 3>> stretch, ratio;  // (value, weight)
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d a = v.row(faces(f, 0)), b = v.row(faces(f, 1)), c = v.row(faces(f, 2));
    const Eigen::Vector3d e1 = (b - a).normalized(), n = (b - a).cross(c - a).normalized(), e2 = n.cross(e1);
    Eigen::Matrix2d P, Q;  // columns: edges ab, ac in the triangle's plane and in UV
    P << (b - a).dot(e1), (c - a).dot(e1), (b - a).dot(e2), (c - a).dot(e2);
    const Eigen::Vector2d ua = uv.row(uv_faces(f, 0)), ub = uv.row(uv_faces(f, 1)), uc = uv.row(uv_faces(f, 2));
    Q.col(0) = ub - ua;
    Q.col(1) = uc - ua;
    const Eigen::Vector2d s = Eigen::JacobiSVD<Eigen::Matrix2d>(Q * P.inverse() / scale).singularValues();
    stretch.push_back({s(0) / s(1), area3[static_cast<size_t>(f)], 0});
    ratio.push_back({s(0) * s(1), area3[static_cast<size_t>(f)], 0});
  }
  auto percentile = [&](std::vector<std::array<double, 3>> values, double q) {
    std::sort(values.begin(), values.end());
    double w = 0;
    for (const auto& x : values) {
      w += x[1];
      if (w >= q * total3) return x[0];
    }
    return values.back()[0];
  };
  return {percentile(stretch, 0.95), percentile(ratio, 0.05), percentile(ratio, 0.95)};
}

void expect_valid_body_layout(const Vertices& v, const Faces& faces, const UvCoordinates& uv, const Faces& uv_faces) {
  ASSERT_EQ(uv_faces.rows(), faces.rows());
  ASSERT_GT(uv.rows(), 0);
  EXPECT_GE(uv.minCoeff(), 0.0);
  EXPECT_LE(uv.maxCoeff(), 1.0);
  // A small margin around the atlas.
  EXPECT_GE(uv.minCoeff(), 0.005);
  EXPECT_LE(uv.maxCoeff(), 0.995);
  // Every triangle counter-clockwise (as the faces are seen from outside) with a positive area:
  // winding is consistent within and across islands, the right side's islands mirrored.
  const Eigen::VectorXd area = uv_signed_areas(uv, uv_faces);
  EXPECT_GT(area.minCoeff(), 0.0);
  EXPECT_TRUE(uv_overlaps(uv, uv_faces).empty());
  // Torso + head front and back, each leg's front and back, two soles, two arms with their
  // palms, two thumbs, eight fingers, the webs between the fingers (three on each hand) and ten
  // toes.
  int islands = 0;
  uv_islands(uv_faces, uv.rows(), &islands);
  EXPECT_EQ(islands, 2 + 4 + 2 + 2 + 2 + 8 + 6 + 10);
  // The atlas is used: the islands cover 45 % of the unit square or more (bounding boxes of
  // tapered islands, packed, leave the rest).
  EXPECT_GT(area.sum(), 0.45);
  // Area-proportional (one scale for all islands: 90 % of the surface within −20 %/+30 % of it)
  // and not badly stretched (95 % of the surface less than 2.6 times longer one way than the
  // other; the worst are the fans at the top of the head and the shoulders' tops).
  const Distortion d = distortion(v, faces, uv, uv_faces);
  EXPECT_LT(d.stretch_p95, 2.6);
  EXPECT_GT(d.area_ratio_p05, 0.8);
  EXPECT_LT(d.area_ratio_p95, 1.3);
  // Seams: only a few vertices take more than one UV.
  EXPECT_LT(uv.rows(), v.rows() * 11 / 10);
  std::printf("UV layout: %d UVs for %d vertices; stretch p95 %.3f, area ratio p05 %.3f p95 %.3f, UV area %.3f\n",
              static_cast<int>(uv.rows()), static_cast<int>(v.rows()), d.stretch_p95, d.area_ratio_p05,
              d.area_ratio_p95, area.sum());
}

}  // namespace

class BuiltinUvLayout : public ::testing::TestWithParam<Sex> {};

TEST_P(BuiltinUvLayout, CommittedModelHasAValidLayout) {
  const BodyModel m = load_model("mannequin", GetParam());
  ASSERT_TRUE(m.has_uvs()) << "rebuild the models: bash scripts/build-models.sh";
  expect_valid_body_layout(m.data().template_vertices, m.faces(), m.data().uv_coordinates, m.data().uv_faces);
  // The stored layout is the generator's, unwrapped from the model's mean body.
  const mannequin::UvLayout again = mannequin::uv_layout(m.data().template_vertices);
  EXPECT_EQ(again.faces, m.data().uv_faces);
  EXPECT_EQ(again.coordinates, m.data().uv_coordinates);
}

INSTANTIATE_TEST_SUITE_P(Sexes, BuiltinUvLayout, ::testing::Values(Sex::Female, Sex::Male, Sex::Neutral),
                         [](const auto& info) { return std::string(to_string(info.param)); });

TEST(MannequinUvLayout, ValidOnGeneratedBodiesAndDeterministic) {
  const mannequin::Topology& topo = mannequin::topology();
  for (Sex sex : {Sex::Female, Sex::Male}) {
    const Vertices v = mannequin::generate(mannequin::typical_dimensions(sex), sex);
    const mannequin::UvLayout a = mannequin::uv_layout(v);
    expect_valid_body_layout(v, topo.faces, a.coordinates, a.faces);
    const mannequin::UvLayout b = mannequin::uv_layout(v);
    ASSERT_EQ(a.coordinates.rows(), b.coordinates.rows());
    EXPECT_EQ(std::memcmp(a.coordinates.data(), b.coordinates.data(), sizeof(double) * static_cast<size_t>(a.coordinates.size())), 0);
    EXPECT_EQ(a.faces, b.faces);
  }
  // Left and right islands are mirror images, so they come in pairs of equal area: all but the
  // torso's front and back.
  const Vertices v = mannequin::generate(mannequin::typical_dimensions(Sex::Female), Sex::Female);
  const mannequin::UvLayout l = mannequin::uv_layout(v);
  int islands = 0;
  const std::vector<int> island = uv_islands(l.faces, l.coordinates.rows(), &islands);
  std::vector<double> area(static_cast<size_t>(islands), 0.0);
  const Eigen::VectorXd a = uv_signed_areas(l.coordinates, l.faces);
  for (size_t f = 0; f < island.size(); ++f) area[static_cast<size_t>(island[f])] += a(static_cast<Eigen::Index>(f));
  int paired = 0;
  for (size_t i = 0; i < area.size(); ++i)
    for (size_t j = 0; j < area.size(); ++j)
      if (i != j && std::abs(area[i] - area[j]) <= 1e-9 * area[i]) {
        ++paired;
        break;
      }
  EXPECT_EQ(paired, 34);  // every island but the torso's front and back has its mirror image
  EXPECT_THROW(mannequin::uv_layout(Vertices(v.topRows(10))), Error);
}
