// avatar_request_from_edge (avatar.h) and measure_person_mesh (measure.h): the one way from values
// as a person types them to a checked request, and the metres check of a person's mesh, shared
// by the CLI and the Python module.
#include <gtest/gtest.h>

#include <string>

#include "caliper/avatar.h"
#include "caliper/measure/input_check.h"
#include "caliper/measure/measure.h"

namespace caliper {
namespace {

EdgeAvatarRequest edge(std::map<std::string, double> values) {
  EdgeAvatarRequest r;
  r.measurements = std::move(values);
  return r;
}

template <class E>
E thrown(const EdgeAvatarRequest& r) {
  try {
    avatar_request_from_edge(r);
  } catch (const E& e) {
    return e;
  }
  ADD_FAILURE() << "no error of the expected type";
  throw std::logic_error("unreachable");
}

TEST(EdgeRequest, ConvertsAliasesToCanonicalSiValues) {
  EdgeAvatarRequest r = edge({{"height", 165}, {"weight", 60}, {"arm_span", 170}});
  r.estimator = "R4";
  r.noise = "self";
  r.noise_sd = {{"height", 2}, {"weight", 1.5}};
  const AvatarRequest q = avatar_request_from_edge(r);
  EXPECT_EQ(q.measurements, (std::map<std::string, double>{{"stature", 1.65}, {"weight", 60}, {"span", 1.70}}));
  EXPECT_EQ(q.regressor, "R4");
  EXPECT_EQ(q.noise, "self");
  EXPECT_EQ(q.noise_sd, (std::map<std::string, double>{{"stature", 0.02}, {"weight", 1.5}}));
  EXPECT_FALSE(q.maps.has_value());
}

TEST(EdgeRequest, NothingGivenNamesTheMeasurements) {
  const Error e = thrown<Error>(edge({}));
  EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
  EXPECT_EQ(e.field(), "measurements");
}

TEST(EdgeRequest, SwappedValuesAreSuspectUnlessForced) {
  EdgeAvatarRequest r = edge({{"stature", 60}, {"weight", 165}});
  const SuspectInputError e = thrown<SuspectInputError>(r);
  EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
  EXPECT_EQ(e.field(), "stature");
  ASSERT_EQ(e.suspects().size(), 2u);
  EXPECT_EQ(e.suspects()[0].suggested, 165);
  EXPECT_EQ(e.suspects()[1].suggested, 60);
  r.force = true;
  EXPECT_EQ(avatar_request_from_edge(r).measurements.at("stature"), 0.60);
}

TEST(EdgeRequest, ASuspectIsFoundUnderItsAliasToo) {
  EXPECT_EQ(thrown<SuspectInputError>(edge({{"height", 1.65}, {"weight", 60}})).field(), "stature");
}

TEST(EdgeRequest, BadValuesNameTheirField) {
  EXPECT_EQ(thrown<Error>(edge({{"height", 165}, {"stature", 166}})).field(), "stature");  // twice, two names
  EXPECT_EQ(thrown<Error>(edge({{"stature", 165}, {"shoe_size", 42}})).field(), "shoe_size");
  EdgeAvatarRequest r = edge({{"stature", 165}, {"weight", 60}});
  r.force = true;
  r.measurements["weight"] = -60;
  EXPECT_EQ(thrown<Error>(r).kind(), ErrorKind::OutOfRange);
  EXPECT_EQ(thrown<Error>(r).field(), "weight");
  r.measurements["weight"] = 60;
  for (double sd : {0.0, -1.0, 51.0, std::nan("")}) {
    r.noise_sd = {{"weight", sd}};
    const Error e = thrown<Error>(r);
    EXPECT_EQ(e.kind(), ErrorKind::OutOfRange) << sd;
    EXPECT_EQ(e.field(), "noise_sd.weight") << sd;
  }
  r.noise_sd = {{"elbow", 1}};
  EXPECT_EQ(thrown<Error>(r).field(), "noise_sd.elbow");
}

// A closed box standing on y = 0, faces counter-clockwise seen from outside.
Mesh box(double width, double height, double depth) {
  Mesh m;
  m.vertices.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.vertices.row(i) << (i & 4 ? width : 0), (i & 2 ? height : 0), (i & 1 ? depth : 0);
  m.faces.resize(12, 3);
  m.faces << 0, 1, 3, 0, 3, 2, 4, 6, 7, 4, 7, 5, 0, 4, 5, 0, 5, 1, 2, 3, 7, 2, 7, 6, 0, 2, 6, 0, 6, 4, 1, 5, 7, 1, 7, 3;
  return m;
}

TEST(PersonMesh, APersonSizedBoxInMetresIsMeasured) {
  const MeshMeasurements m = measure_person_mesh(box(0.5, 1.6, 0.25), WeightFromVolume{1000, -2}, "mesh");
  EXPECT_DOUBLE_EQ(m.stature, 1.6);
  EXPECT_NEAR(m.volume, 0.2, 1e-15);
  EXPECT_NEAR(m.weight, 198, 1e-12);
}

TEST(PersonMesh, AMeshInCentimetresOrMillimetresIsRefusedNamingTheField) {
  for (double scale : {100.0, 1000.0, 0.1}) {
    Mesh m = box(0.5, 1.6, 0.25);
    m.vertices *= scale;
    try {
      measure_person_mesh(m, WeightFromVolume{1000, -2}, "--mesh");
      ADD_FAILURE() << "scale " << scale << " was accepted";
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), ErrorKind::OutOfRange);
      EXPECT_EQ(e.field(), "--mesh");
      EXPECT_NE(std::string(e.what()).find("read in metres"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace caliper
