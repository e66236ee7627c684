// Creases (dihedral angles) on tiny meshes with exact answers, and the per-region report.
#include <gtest/gtest.h>

#include <cmath>

#include "caliper/body/crease.h"
#include "caliper/errors.h"
#include "fixtures.h"

using namespace caliper;

TEST(Crease, CubeEdgesBendNinetyDegreesAndItsDiagonalsNone) {
  const Mesh cube = test::unit_cube();
  const auto bends = dihedral_angles(cube.vertices, cube.faces);
  ASSERT_EQ(bends.size(), 18u);  // 12 cube edges + 6 face diagonals
  int right = 0, flat = 0;
  for (const auto& e : bends) {
    EXPECT_LT(e.a, e.b);
    if (std::abs(e.degrees - 90) < 1e-9) ++right;
    if (std::abs(e.degrees) < 1e-9) ++flat;
  }
  EXPECT_EQ(right, 12);
  EXPECT_EQ(flat, 6);
}

TEST(Crease, PrismSidesBendByTheExteriorAngleOfThePolygon) {
  const int sides = 12;
  const Mesh p = test::prism(sides, 3, 0.2, 1.0);
  int vertical = 0;
  for (const auto& e : dihedral_angles(p.vertices, p.faces)) {
    const bool on_wall = e.a < 3 * sides && e.b < 3 * sides;
    if (on_wall && e.b - e.a == sides) {  // a vertical edge between two side quads
      EXPECT_NEAR(e.degrees, 360.0 / sides, 1e-9);
      ++vertical;
    }
  }
  EXPECT_EQ(vertical, 2 * sides);
}

TEST(Crease, RegularTetrahedronFacesMeetAtItsKnownAngle) {
  Mesh t;
  t.vertices.resize(4, 3);
  t.vertices << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  t.faces.resize(4, 3);
  t.faces << 0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2;
  // Interior dihedral angle acos(1/3) = 70.53°; the normals differ by its supplement.
  for (const auto& e : dihedral_angles(t.vertices, t.faces)) EXPECT_NEAR(e.degrees, 180 - std::acos(1.0 / 3) * 180 / M_PI, 1e-9);
}

TEST(Crease, BoundaryEdgesHaveNoAngle) {
  Mesh tri;
  tri.vertices.resize(3, 3);
  tri.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  tri.faces.resize(1, 3);
  tri.faces << 0, 1, 2;
  EXPECT_TRUE(dihedral_angles(tri.vertices, tri.faces).empty());
}

TEST(Crease, JointNamesMapToRegions) {
  EXPECT_EQ(region_of_joint("pelvis"), BodyRegion::Torso);
  EXPECT_EQ(region_of_joint("spine3"), BodyRegion::Torso);
  EXPECT_EQ(region_of_joint("head"), BodyRegion::HeadNeck);
  EXPECT_EQ(region_of_joint("left_collar"), BodyRegion::Arms);
  EXPECT_EQ(region_of_joint("right_shoulder"), BodyRegion::Arms);
  EXPECT_EQ(region_of_joint("left_wrist"), BodyRegion::Hands);
  EXPECT_EQ(region_of_joint("right_hand"), BodyRegion::Hands);
  EXPECT_EQ(region_of_joint("left_thumb2"), BodyRegion::Hands);
  EXPECT_EQ(region_of_joint("right_ring3"), BodyRegion::Hands);
  EXPECT_EQ(region_of_joint("left_knee"), BodyRegion::Legs);
  EXPECT_EQ(region_of_joint("right_foot"), BodyRegion::Feet);
  EXPECT_TRUE(is_feature_region(BodyRegion::Hands));
  EXPECT_FALSE(is_feature_region(BodyRegion::Arms));
}

// A prism whose lower rings belong to a leg and upper rings to the torso: the edges joining the
// two regions count in the leg (the region farther from the torso), the caps' in their own.
TEST(Crease, ReportSplitsByRegionAndCountsJunctionsInTheLimb) {
  const int sides = 8, rings = 4;
  const Mesh p = test::prism(sides, rings, 0.1, 0.5);
  std::vector<BodyRegion> regions(static_cast<size_t>(p.vertices.rows()), BodyRegion::Torso);
  for (int v = 0; v < 2 * sides; ++v) regions[static_cast<size_t>(v)] = BodyRegion::Legs;
  regions[static_cast<size_t>(rings * sides)] = BodyRegion::Legs;  // bottom cap centre
  const auto report = crease_report(p.vertices, p.faces, regions);
  ASSERT_EQ(report.size(), 2u);
  EXPECT_EQ(report[0].region, BodyRegion::Torso);
  EXPECT_EQ(report[1].region, BodyRegion::Legs);
  const auto all = dihedral_angles(p.vertices, p.faces);
  EXPECT_EQ(report[0].edges + report[1].edges, static_cast<std::int64_t>(all.size()));
  // Leg: the bottom cap's spokes and rim (2·sides edges), ring 0→1 with ring 1's own edges
  // (3·sides), and the junction's verticals and diagonals from ring 1 to ring 2 (2·sides).
  EXPECT_EQ(report[1].edges, 7 * sides);
  // The cap's rim is the sharpest fold: 90° between the wall and the flat cap.
  EXPECT_NEAR(report[1].max_degrees, 90, 1e-9);
  EXPECT_NEAR(report[0].max_degrees, 90, 1e-9);
  EXPECT_NEAR(smooth_region_max_crease(report), 90, 1e-9);
  regions.pop_back();
  EXPECT_THROW(crease_report(p.vertices, p.faces, regions), Error);
}

TEST(Crease, ModelReportTakesRegionsFromTheSkinWeights) {
  const BodyModel toy = test::toy_model();
  const auto report = crease_report(toy, toy.rest_vertices(Eigen::VectorXd()));
  ASSERT_FALSE(report.empty());
  std::int64_t edges = 0;
  for (const auto& r : report) edges += r.edges;
  EXPECT_EQ(edges, static_cast<std::int64_t>(dihedral_angles(toy.rest_vertices(Eigen::VectorXd()), toy.faces()).size()));
}
