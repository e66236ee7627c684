// Tiny meshes with exact answers: volumes, sections, convex hulls, topology checks.
#include <gtest/gtest.h>

#include "fixtures.h"

#include <cmath>
#include <numbers>

using namespace caliper;

TEST(Geometry, UnitCubeVolumeIsOne) {
  const Mesh cube = test::unit_cube();
  EXPECT_NEAR(signed_volume(cube.vertices, cube.faces), 1.0, 1e-15);
}

TEST(Geometry, VolumeDoesNotDependOnPosition) {
  Mesh cube = test::unit_cube();
  cube.vertices.rowwise() += Eigen::RowVector3d(5, -3, 2);
  EXPECT_NEAR(signed_volume(cube.vertices, cube.faces), 1.0, 1e-12);
}

TEST(Geometry, FlippedCubeHasNegativeVolume) {
  Mesh cube = test::unit_cube();
  cube.faces.col(1).swap(cube.faces.col(2));
  EXPECT_NEAR(signed_volume(cube.vertices, cube.faces), -1.0, 1e-15);
}

TEST(Geometry, PrismVolumeIsAreaTimesHeight) {
  const int sides = 12;
  const double r = 0.2, h = 1.5;
  const Mesh p = test::prism(sides, 4, r, h);
  const double area = 0.5 * sides * r * r * std::sin(2 * M_PI / sides);
  EXPECT_NEAR(signed_volume(p.vertices, p.faces), area * h, 1e-12);
}

// The volume's gradient in the vertices, against central differences on a prism (the volume
// is cubic in each vertex's coordinates, so a central difference is exact up to rounding).
TEST(Geometry, VolumeGradientMatchesDifferences) {
  const auto p = test::prism(7, 3, 0.3, 1.2);
  Eigen::VectorXd g;
  EXPECT_NEAR(signed_volume(p.vertices, p.faces, g), signed_volume(p.vertices, p.faces), 1e-15);
  ASSERT_EQ(g.size(), p.vertices.size());
  const double h = 1e-5;
  for (Eigen::Index i = 0; i < g.size(); ++i) {
    Vertices up = p.vertices, down = p.vertices;
    up(i / 3, i % 3) += h;
    down(i / 3, i % 3) -= h;
    EXPECT_NEAR(g(i), (signed_volume(up, p.faces) - signed_volume(down, p.faces)) / (2 * h), 1e-9) << "coordinate " << i;
  }
}

TEST(Geometry, CubeIsClosedManifoldAndOriented) {
  const Mesh cube = test::unit_cube();
  const MeshCheck c = check_mesh(cube.faces, 8);
  EXPECT_TRUE(c.closed);
  EXPECT_TRUE(c.manifold);
  EXPECT_TRUE(c.consistently_oriented);
  EXPECT_EQ(c.boundary_edges, 0);
}

TEST(Geometry, CheckFindsHoleAndBadOrientation) {
  Mesh cube = test::unit_cube();
  Faces open = cube.faces.topRows(11);
  const MeshCheck holed = check_mesh(open, 8);
  EXPECT_FALSE(holed.closed);
  EXPECT_EQ(holed.boundary_edges, 3);
  Faces flipped = cube.faces;
  std::swap(flipped(0, 1), flipped(0, 2));
  EXPECT_FALSE(check_mesh(flipped, 8).consistently_oriented);
}

TEST(Geometry, SectionOfPrismIsItsPolygon) {
  const int sides = 16;
  const double r = 0.1;
  const Mesh p = test::prism(sides, 5, r, 1.0);
  auto loops = plane_section(p.vertices, p.faces, {0, 0.37, 0}, {0, 1, 0});
  ASSERT_EQ(loops.size(), 1u);
  // Each side quad is two triangles: the plane crosses the vertical edges and the diagonals.
  EXPECT_EQ(loops[0].size(), static_cast<size_t>(2 * sides));
  for (const auto& q : loops[0]) EXPECT_NEAR(q.y(), 0.37, 1e-12);
  std::vector<Eigen::Vector2d> flat;
  for (const auto& q : loops[0]) flat.push_back({q.x(), q.z()});
  EXPECT_NEAR(convex_hull_perimeter(flat), 2 * sides * r * std::sin(M_PI / sides), 1e-12);
}

TEST(Geometry, SectionThroughVertexPlaneStillOneLoop) {
  // The plane passes exactly through a ring of vertices: the nudge keeps one closed loop.
  const Mesh p = test::prism(10, 5, 0.1, 1.0);
  auto loops = plane_section(p.vertices, p.faces, {0, 0.5, 0}, {0, 1, 0});
  ASSERT_EQ(loops.size(), 1u);
  std::vector<Eigen::Vector2d> flat;
  for (const auto& q : loops[0]) flat.push_back({q.x(), q.z()});
  EXPECT_NEAR(convex_hull_perimeter(flat), 20 * 0.1 * std::sin(M_PI / 10), 1e-9);
}

TEST(Geometry, TwoSeparateBodiesGiveTwoLoops) {
  Mesh a = test::prism(8, 3, 0.1, 1.0), b = a;
  b.vertices.col(0).array() += 0.5;
  Mesh both;
  both.vertices.resize(a.vertices.rows() * 2, 3);
  both.vertices << a.vertices, b.vertices;
  both.faces.resize(a.faces.rows() * 2, 3);
  both.faces << a.faces, (b.faces.array() + static_cast<int>(a.vertices.rows())).matrix();
  EXPECT_EQ(plane_section(both.vertices, both.faces, {0, 0.5, 0}, {0, 1, 0}).size(), 2u);
}

TEST(Geometry, ConvexHullIgnoresConcavity) {
  // A square with a notch: the tape spans the notch, so the perimeter is the square's.
  std::vector<Eigen::Vector2d> pts = {{0, 0}, {1, 0}, {1, 1}, {0.5, 0.5}, {0, 1}};
  EXPECT_NEAR(convex_hull_perimeter(pts), 4.0, 1e-15);
}

TEST(Geometry, NormalsOfCubeCornerPointOutwards) {
  const Mesh cube = test::unit_cube();
  const Vertices n = vertex_normals(cube.vertices, cube.faces);
  for (int v = 0; v < 8; ++v) {
    const Eigen::Vector3d out = cube.vertices.row(v).transpose() - Eigen::Vector3d(0.5, 0.5, 0.5);
    EXPECT_GT(n.row(v).dot(out.transpose()), 0.0);
    EXPECT_NEAR(n.row(v).norm(), 1.0, 1e-12);
  }
}

// Rings on a unit sphere, 1° of latitude apart below the equator and 15° above it (as the body's
// rings are 1.6 mm apart under the head's widest ring and 13 mm over it): every vertex's normal is
// its radius, the equator's too. Weighting the faces by area tilted the equator's normals about
// 7° toward the larger faces above, a band in the shading.
TEST(Geometry, NormalsOnUnevenRingsOfASphereAreRadial) {
  std::vector<double> latitudes;
  for (int d = -30; d <= 0; ++d) latitudes.push_back(d);
  latitudes.insert(latitudes.end(), {15.0, 30.0, 45.0});
  const int columns = 48, rings = static_cast<int>(latitudes.size());
  Vertices v(rings * columns, 3);
  for (int r = 0; r < rings; ++r)
    for (int c = 0; c < columns; ++c) {
      const double lat = latitudes[static_cast<size_t>(r)] * std::numbers::pi / 180, lon = 2 * std::numbers::pi * c / columns;
      v.row(r * columns + c) << std::cos(lat) * std::cos(lon), std::sin(lat), -std::cos(lat) * std::sin(lon);
    }
  Faces f(2 * (rings - 1) * columns, 3);
  int n = 0;
  for (int r = 0; r + 1 < rings; ++r)
    for (int c = 0; c < columns; ++c) {
      const int a = r * columns + c, b = r * columns + (c + 1) % columns, up = a + columns, up_b = b + columns;
      f.row(n++) << a, b, up_b;
      f.row(n++) << a, up_b, up;
    }
  const Vertices normals = vertex_normals(v, f);
  for (int r = 1; r + 1 < rings; ++r)  // the first and last rings have faces on one side only
    for (int c = 0; c < columns; ++c) {
      const Eigen::Vector3d radius = v.row(r * columns + c), normal = normals.row(r * columns + c);
      EXPECT_LT(std::acos(std::min(1.0, normal.dot(radius))) * 180 / std::numbers::pi, 0.05)
          << "ring at latitude " << latitudes[static_cast<size_t>(r)] << "°, column " << c;
    }
}

TEST(Geometry, ClosedCubeHasNoSelfIntersections) {
  const Mesh cube = test::unit_cube();
  EXPECT_TRUE(self_intersections(cube.vertices, cube.faces).empty());
}

TEST(Geometry, TwoCubesPushedIntoEachOtherIntersect) {
  // Two unit cubes in one mesh, the second shifted by half a unit along x and a quarter along y:
  // their side walls cross. Shifted by two units they are apart.
  const Mesh cube = test::unit_cube();
  auto two = [&](double dx, double dy) {
    Mesh m;
    m.vertices.resize(2 * cube.vertices.rows(), 3);
    m.vertices << cube.vertices, cube.vertices.rowwise() + Eigen::RowVector3d(dx, dy, 0.1);
    m.faces.resize(2 * cube.faces.rows(), 3);
    m.faces << cube.faces, cube.faces.array() + static_cast<std::int32_t>(cube.vertices.rows());
    return m;
  };
  const Mesh crossing = two(0.5, 0.25), apart = two(2.0, 0.0);
  EXPECT_FALSE(self_intersections(crossing.vertices, crossing.faces).empty());
  EXPECT_TRUE(self_intersections(apart.vertices, apart.faces).empty());
  EXPECT_EQ(self_intersections(crossing.vertices, crossing.faces, 1).size(), 1u);
}

TEST(Geometry, ACrossingPairSpanningManyGridCellsIsReportedOnce) {
  // Two hundred 1 mm triangles far off make the grid's cells about 3 cm; two 1 m triangles that
  // cross each other then share dozens of cells along their crossing, and must come out as one pair.
  Mesh m;
  const int tiny = 200;
  m.vertices.resize(3 * tiny + 6, 3);
  m.faces.resize(tiny + 2, 3);
  for (int i = 0; i < tiny; ++i) {
    const Eigen::RowVector3d at(10.0 + 0.01 * i, 0, 0);
    m.vertices.row(3 * i) = at;
    m.vertices.row(3 * i + 1) = at + Eigen::RowVector3d(0.001, 0, 0);
    m.vertices.row(3 * i + 2) = at + Eigen::RowVector3d(0, 0.001, 0);
    m.faces.row(i) << 3 * i, 3 * i + 1, 3 * i + 2;
  }
  m.vertices.bottomRows(6) << 0, 0, 0, 1, 0, 0, 0, 1, 0,                // in the plane z = 0
      0.25, -0.5, -0.5, 0.25, 1, -0.5, 0.25, 0.25, 0.5;                  // in the plane x = 0.25
  m.faces.row(tiny) << 3 * tiny, 3 * tiny + 1, 3 * tiny + 2;
  m.faces.row(tiny + 1) << 3 * tiny + 3, 3 * tiny + 4, 3 * tiny + 5;
  const auto hits = self_intersections(m.vertices, m.faces);
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(hits[0], std::make_pair(tiny, tiny + 1));
}
