// Pose files (src/body/pose.cpp, pose_from_json): `caliper avatar --pose FILE` and the API's
// "pose" member, put on the built-in body's 54 joints. Oracles: an accepted pose has one finite
// row per joint, and the same rows written as [x, y, z] triples read back bit for bit.
#include <nlohmann/json.hpp>

#include "caliper/body/pose.h"
#include "caliper/io/model_files.h"
#include "fuzz_support.h"

using namespace caliper;

namespace {

const BodyModel& body() {
  static const BodyModel model = load_model("mannequin", Sex::Neutral);
  return model;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Pose pose;
  if (!fuzz::accepts([&] { pose = pose_from_json(body(), fuzz::as_string(data, size), "fuzz.json"); })) return 0;
  fuzz::check(pose.rows() == body().joint_count() && pose.allFinite(), "a pose without one finite row per joint");

  nlohmann::json triples = nlohmann::json::array();
  for (Eigen::Index j = 0; j < pose.rows(); ++j) triples.push_back({pose(j, 0), pose(j, 1), pose(j, 2)});
  Pose again;
  fuzz::check(fuzz::accepts([&] { again = pose_from_json(body(), nlohmann::json{{"pose", triples}}.dump(), "again"); }),
              "a pose written as triples is refused");
  fuzz::check(again == pose, "a pose changed in a round trip");
  return 0;
}
