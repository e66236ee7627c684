// UV layouts: the overlap checker on tiny triangles with known answers and the model's
// validation of its UV arrays.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cstring>
#include <functional>
#include <numeric>

#include "caliper/caliper.h"
#include "fixtures.h"

using namespace caliper;

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
