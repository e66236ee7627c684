// The capture protocol engine on synthetic sample streams (test_capture_script.h): a scripted
// person with known landmarks, tracking jitter, short presses, drift, dropped frames, duplicate
// and out-of-order timestamps, swapped controllers, ISAK third repetitions, undo/redo, bad input.
// Expected values come from the landmarks (hand-computed distances), never from the engine.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "caliper/capture/profiles.h"
#include "caliper/capture/protocol.h"
#include "caliper/errors.h"
#include "caliper/vocabulary/catalogue.h"
#include "test_capture_script.h"

namespace caliper::capture {
namespace {

using test::SampleScript;
using test::ScriptedPerson;

const Eigen::Vector3d kOffset(0, -0.005, 0.05);

std::vector<CaptureEvent> feed_all(CaptureProtocol& p, SampleScript& s, const Eigen::Vector3d& offset = kOffset) {
  std::vector<CaptureEvent> events;
  for (const auto& b : s.batches()) {
    auto e = p.feed(b, offset);
    events.insert(events.end(), e.begin(), e.end());
  }
  return events;
}

int count(const std::vector<CaptureEvent>& ev, EventType type) {
  return static_cast<int>(std::count_if(ev.begin(), ev.end(), [&](const CaptureEvent& e) { return e.type == type; }));
}

const CaptureEvent* first(const std::vector<CaptureEvent>& ev, EventType type) {
  for (const auto& e : ev)
    if (e.type == type) return &e;
  return nullptr;
}

// Jitter is ±1 mm per axis; the median over ~70 samples is well inside 1 mm of the truth.
constexpr double kTolCm = 0.1;

TEST(CaptureProtocol, FullCoreSessionReproducesTheLandmarkDistances) {
  ScriptedPerson person;
  SampleScript s(kOffset);
  CaptureProtocol p({});
  EXPECT_EQ(p.state(), SessionState::Floor);
  ASSERT_TRUE(p.current_step());
  EXPECT_EQ(p.current_step()->points_needed, 5);
  test::script_floor(s, person);
  auto ev = feed_all(p, s);
  EXPECT_EQ(count(ev, EventType::PointAccepted), 5);
  EXPECT_EQ(count(ev, EventType::PointRejected), 0);
  ASSERT_TRUE(p.floor_m());
  EXPECT_NEAR(*p.floor_m(), person.floor, 0.002);  // median of the five taps (±2 mm floor)
  EXPECT_EQ(p.state(), SessionState::Measuring);
  EXPECT_EQ(p.current_step()->spec.name, "stature");

  test::script_core(s, person);
  ev = feed_all(p, s);
  EXPECT_EQ(count(ev, EventType::PointAccepted), 10);
  EXPECT_EQ(count(ev, EventType::StepDone), 5);
  EXPECT_EQ(count(ev, EventType::SessionDone), 1);
  EXPECT_EQ(p.state(), SessionState::Entries);
  EXPECT_EQ(p.steps_done(), 6);
  EXPECT_EQ(p.steps_total(), 6);
  const auto set = p.measurement_set();
  // Heights are measured above the calibrated floor, so the ±2 mm floor median adds to them.
  EXPECT_NEAR(set.at("stature"), person.stature() * 100, 0.25);
  EXPECT_NEAR(set.at("crotch_height"), person.crotch_height() * 100, 0.25);
  EXPECT_NEAR(set.at("span"), person.span() * 100, kTolCm);
  EXPECT_NEAR(set.at("hip_breadth"), person.hip_breadth() * 100, kTolCm);
  EXPECT_NEAR(set.at("arm_length"), person.arm_length() * 100, kTolCm);
  EXPECT_EQ(set.count("weight"), 0u);

  p.set_sex(Sex::Female);
  EXPECT_EQ(p.state(), SessionState::Entries);
  p.set_weight_kg(61.5);
  EXPECT_EQ(p.state(), SessionState::Done);
  EXPECT_DOUBLE_EQ(p.measurement_set().at("weight"), 61.5);
  EXPECT_FALSE(p.current_step());
}

TEST(CaptureProtocol, TipOffsetIsRotatedByTheGripOrientation) {
  // Grip 5 cm above the floor, rotated 90° about X: the +Z offset of 5 cm points straight down,
  // so the tip touches y = 0 exactly.
  CaptureProtocol p({});
  const Eigen::Quaterniond q(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));
  std::vector<ControllerSample> b;
  for (int i = 0; i < 80; ++i) {
    ControllerSample c;
    c.t = i / 72.0;
    c.hand = Hand::Left;
    c.position = Eigen::Vector3d(0.1, 0.05, 0.2);
    c.orientation = Eigen::Vector4d(q.x(), q.y(), q.z(), q.w());
    c.trigger = i < 78 ? 1.0 : 0.0;
    b.push_back(c);
  }
  auto ev = p.feed(b, Eigen::Vector3d(0, 0, 0.05));
  const CaptureEvent* a = first(ev, EventType::PointAccepted);
  ASSERT_TRUE(a);
  EXPECT_NEAR(*a->value_cm, 0.0, 1e-9);
  EXPECT_NEAR(a->point->tip.z(), 0.2, 1e-12);
}

TEST(CaptureProtocol, ShortPressIsRejectedWithTheHoldTime) {
  ScriptedPerson person;
  SampleScript s(kOffset);
  CaptureProtocol p({});
  s.hold(1, Eigen::Vector3d(0, person.floor, 0.3), 0.4);
  auto ev = feed_all(p, s);
  EXPECT_EQ(count(ev, EventType::PointAccepted), 0);
  const CaptureEvent* r = first(ev, EventType::PointRejected);
  ASSERT_TRUE(r);
  EXPECT_NE(r->reason.find("held 0.4 s"), std::string::npos) << r->reason;
  EXPECT_NE(r->reason.find("1 s"), std::string::npos) << r->reason;
  EXPECT_EQ(p.current_step()->points_done, 0);
}

TEST(CaptureProtocol, DriftDuringAHoldIsRejectedAndAStillHoldIsNot) {
  ScriptedPerson person;
  SampleScript s(kOffset);
  CaptureProtocol p({});
  s.drift[1] = Eigen::Vector3d(0.04, 0, 0);  // 4 cm/s: about 4 cm over the 1 s hold
  s.hold(1, Eigen::Vector3d(0, person.floor, 0.3), 1.2);
  auto ev = feed_all(p, s);
  const CaptureEvent* r = first(ev, EventType::PointRejected);
  ASSERT_TRUE(r);
  EXPECT_NE(r->reason.find("moved"), std::string::npos) << r->reason;
  EXPECT_NE(r->reason.find("keep still"), std::string::npos) << r->reason;
  EXPECT_EQ(count(ev, EventType::PointAccepted), 0);
  // A slow drift under the threshold (0.5 cm/s → ±0.25 cm around the median) is a still hold.
  s.drift[1] = Eigen::Vector3d(0.005, 0, 0);
  s.hold(1, Eigen::Vector3d(0, person.floor, 0.3), 1.2);
  ev = feed_all(p, s);
  EXPECT_EQ(count(ev, EventType::PointAccepted), 1);
}

TEST(CaptureProtocol, AHeldTriggerGivesOnePointUntilReleased) {
  ScriptedPerson person;
  SampleScript s(kOffset);
  CaptureProtocol p({});
  s.hold(1, Eigen::Vector3d(0, person.floor, 0.3), 3.5);  // held 3.5 s: one point, not three
  auto ev = feed_all(p, s);
  EXPECT_EQ(count(ev, EventType::PointAccepted), 1);
  EXPECT_EQ(count(ev, EventType::PointRejected), 0);
}

TEST(CaptureProtocol, DroppedFramesAreToleratedAndLongGapsVoidTheHold) {
  ScriptedPerson person;
  SampleScript s(kOffset);
  CaptureProtocol p({});
  // Every other frame dropped and a 0.2 s hole in the middle of the hold: still a good point.
  s.hold(1, Eigen::Vector3d(0, person.floor, 0.3), 1.2);
  std::vector<ControllerSample> kept;
  for (size_t i = 0; i < s.samples.size(); ++i) {
    const double t = s.samples[i].t;
    if ((i / 2) % 2 == 0 && !(t > 10.8 && t < 11.0)) kept.push_back(s.samples[i]);
  }
  s.samples = kept;
  auto ev = feed_all(p, s);
  EXPECT_EQ(count(ev, EventType::PointAccepted), 1);
  EXPECT_EQ(count(ev, EventType::PointRejected), 0);

  // Tracking lost for 0.6 s during the hold: rejected, and says why.
  s.tip[1] = Eigen::Vector3d(0.2, person.floor, 0.2);
  s.run(0.3);
  s.trigger[1] = 1;
  s.run(0.3);
  s.tracked[1] = false;
  s.run(0.6);
  s.tracked[1] = true;
  s.run(0.8);
  s.trigger[1] = 0;
  s.run(0.3);
  ev = feed_all(p, s);
  const CaptureEvent* r = first(ev, EventType::PointRejected);
  ASSERT_TRUE(r);
  EXPECT_NE(r->reason.find("tracking stopped"), std::string::npos) << r->reason;
  EXPECT_EQ(count(ev, EventType::PointAccepted), 0);  // the trigger stayed down: no second point
  EXPECT_EQ(p.current_step()->points_done, 1);
}

TEST(CaptureProtocol, DuplicateAndOutOfOrderSamplesGiveTheSameResult) {
  ScriptedPerson person;
  SampleScript clean_script(kOffset, 3), messy_script(kOffset, 3);
  CaptureProtocol clean({}), messy({});
  test::script_floor(clean_script, person);
  test::script_floor(messy_script, person);
  feed_all(clean, clean_script);
  // Same samples, each batch shuffled, every 5th sample sent twice, and an old batch re-sent.
  std::mt19937 rng(11);
  auto batches = messy_script.batches();
  std::vector<ControllerSample> stale = batches.front();
  for (size_t i = 0; i < batches.size(); ++i) {
    auto b = batches[i];
    for (size_t k = 0; k < batches[i].size(); k += 5) b.push_back(batches[i][k]);
    std::shuffle(b.begin(), b.end(), rng);
    messy.feed(b, kOffset);
    if (i == batches.size() / 2) messy.feed(stale, kOffset);
  }
  ASSERT_TRUE(clean.floor_m() && messy.floor_m());
  EXPECT_DOUBLE_EQ(*clean.floor_m(), *messy.floor_m());
  EXPECT_EQ(clean.points().size(), messy.points().size());
  EXPECT_GT(messy.ignored_samples(), 0u);
  EXPECT_EQ(clean.ignored_samples(), 0u);
}

TEST(CaptureProtocol, SwappedControllerLabelsChangeNothing) {
  ScriptedPerson person;
  SampleScript a(kOffset, 5), b(kOffset, 5);
  b.swap_labels = true;
  CaptureProtocol pa({}), pb({});
  for (auto* s : {&a, &b}) {
    test::script_floor(*s, person);
    test::script_core(*s, person);
  }
  feed_all(pa, a);
  feed_all(pb, b);
  ASSERT_EQ(pa.state(), SessionState::Entries);
  ASSERT_EQ(pb.state(), SessionState::Entries);
  for (const auto& [name, value] : pa.measurement_set()) EXPECT_DOUBLE_EQ(pb.measurement_set().at(name), value) << name;
  EXPECT_EQ(pb.points()[5].hand, Hand::Left);  // stature taken with the controller labelled left
}

TEST(CaptureProtocol, IsakAsksForAThirdRepetitionAndTakesTheMedian) {
  ScriptedPerson person;
  SampleScript s(kOffset, 9, 0.0);  // no jitter: exact values
  CaptureProtocol p({});
  test::script_floor(s, person);
  feed_all(p, s);
  const double floor = *p.floor_m();
  // 170 cm then 175 cm: 2.9 % apart, more than ISAK's 1.5 %.
  s.hold(1, Eigen::Vector3d(0, floor + 1.70, 0), 1.2);
  s.hold(1, Eigen::Vector3d(0, floor + 1.75, 0), 1.2);
  auto ev = feed_all(p, s);
  EXPECT_EQ(count(ev, EventType::StepDone), 0);
  ASSERT_EQ(p.current_step()->spec.name, "stature");
  EXPECT_EQ(p.current_step()->repetition, 3);
  EXPECT_EQ(p.current_step()->repetitions_needed, 3);
  EXPECT_FALSE(p.values().front().value_m);
  s.hold(1, Eigen::Vector3d(0, floor + 1.71, 0), 1.2);
  ev = feed_all(p, s);
  ASSERT_EQ(count(ev, EventType::StepDone), 1);
  EXPECT_NEAR(*first(ev, EventType::StepDone)->value_cm, 171.0, 1e-9);
  EXPECT_EQ(p.values().front().rule, IsakRule::MedianOfThree);
  EXPECT_EQ(p.current_step()->spec.name, "span");
  EXPECT_EQ(p.current_step()->repetitions_needed, 2);
}

TEST(CaptureProtocol, UndoRemovesTheLastPointAndRedoRestoresIt) {
  ScriptedPerson person;
  SampleScript s(kOffset, 9, 0.0);
  CaptureProtocol p({});
  EXPECT_FALSE(p.undo());
  EXPECT_FALSE(p.redo());
  test::script_floor(s, person);
  s.hold(1, person.head_top, 1.2);
  s.hold(1, person.head_top, 1.2);
  feed_all(p, s);
  ASSERT_EQ(p.current_step()->spec.name, "span");
  ASSERT_TRUE(p.values().front().value_m);
  const double stature = *p.values().front().value_m;

  EXPECT_TRUE(p.undo());  // the second stature repetition
  EXPECT_EQ(p.current_step()->spec.name, "stature");
  EXPECT_EQ(p.current_step()->repetition, 2);
  EXPECT_FALSE(p.values().front().value_m);
  EXPECT_EQ(p.measurement_set().count("stature"), 0u);
  EXPECT_TRUE(p.undo());
  EXPECT_TRUE(p.undo());  // the fifth floor tap: back to the floor step
  EXPECT_EQ(p.state(), SessionState::Floor);
  EXPECT_FALSE(p.floor_m());
  EXPECT_EQ(p.current_step()->points_done, 4);

  EXPECT_TRUE(p.redo());
  EXPECT_TRUE(p.redo());
  EXPECT_TRUE(p.redo());
  EXPECT_FALSE(p.redo());
  EXPECT_EQ(p.current_step()->spec.name, "span");
  EXPECT_DOUBLE_EQ(*p.values().front().value_m, stature);

  // A new point after an undo ends the redo list.
  EXPECT_TRUE(p.undo());
  s.hold(1, person.head_top, 1.2);
  feed_all(p, s);
  EXPECT_TRUE(p.redo_points().empty());
  EXPECT_FALSE(p.redo());
}

TEST(CaptureProtocol, NaNAndBadSamplesAreRefusedNamingTheFieldAndChangeNothing) {
  CaptureProtocol p({});
  std::vector<ControllerSample> b(3);
  for (int i = 0; i < 3; ++i) b[i].t = i * 0.01, b[i].trigger = 1;
  b[1].position.y() = std::nan("");
  try {
    p.feed(b, kOffset);
    FAIL() << "NaN accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "samples[1].position");
    EXPECT_EQ(e.kind(), ErrorKind::InvalidArgument);
  }
  b[1].position.y() = 0;
  b[2].orientation = Eigen::Vector4d(0, 0, 0, 0);
  try {
    p.feed(b, kOffset);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "samples[2].orientation");
  }
  b[2].orientation = Eigen::Vector4d(0, 0, 0, 1);
  b[0].trigger = 1.5;
  try {
    p.feed(b, kOffset);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "samples[0].trigger");
  }
  b[0].trigger = 0;
  b[0].t = INFINITY;
  try {
    p.feed(b, kOffset);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "samples[0].t");
  }
  std::vector<ControllerSample> huge(kMaxSamplesPerBatch + 1);
  try {
    p.feed(huge, kOffset);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "samples");
  }
  EXPECT_EQ(p.ignored_samples(), 0u);  // nothing of the refused batches was taken
  EXPECT_TRUE(p.points().empty());
}

TEST(CaptureProtocol, ANewClockAfterAPageReloadIsFollowed) {
  ScriptedPerson person;
  SampleScript s(kOffset);
  CaptureProtocol p({});
  s.t = 500;
  s.hold(1, Eigen::Vector3d(0, person.floor, 0.3), 1.2);
  feed_all(p, s);
  s.t = 2;  // performance.now() restarted
  s.hold(1, Eigen::Vector3d(0.1, person.floor, 0.3), 1.2);
  auto ev = feed_all(p, s);
  EXPECT_EQ(count(ev, EventType::PointAccepted), 1);
  EXPECT_EQ(p.points().size(), 2u);
}

TEST(CaptureProtocol, ImplausibleValuesAreRejected) {
  ScriptedPerson person;
  SampleScript s(kOffset, 9, 0.0);
  CaptureProtocol p({});
  s.hold(1, Eigen::Vector3d(0, 0.9, 0), 1.2);  // a "floor" tap 90 cm up
  auto ev = feed_all(p, s);
  ASSERT_TRUE(first(ev, EventType::PointRejected));
  EXPECT_NE(first(ev, EventType::PointRejected)->reason.find("touch the floor"), std::string::npos);
  test::script_floor(s, person);
  s.hold(1, person.head_top, 1.2);
  s.hold(1, person.head_top, 1.2);
  feed_all(p, s);
  ASSERT_EQ(p.current_step()->spec.name, "span");
  const Eigen::Vector3d a(0, 1.4, 0), b(0.1, 1.4, 0);  // 10 cm "span"
  s.hold(0, a, 1.2, &b);
  ev = feed_all(p, s);
  ASSERT_TRUE(first(ev, EventType::PointRejected));
  EXPECT_NE(first(ev, EventType::PointRejected)->reason.find("outside the accepted range of span"), std::string::npos)
      << first(ev, EventType::PointRejected)->reason;
}

TEST(CaptureProtocol, InstructionsFollowTheMode) {
  CaptureProtocol self({Mode::Self, StepSet::Core, {}}), other({Mode::Other, StepSet::Core, {}});
  EXPECT_NE(self.current_step()->instruction, other.current_step()->instruction);
  for (const auto& s : capture_steps(StepSet::All)) {
    EXPECT_EQ(s.instruction_other.find(" your "), std::string::npos) << s.name;
    EXPECT_NE(s.instruction_self.find("second"), std::string::npos) << s.name;
  }
}

TEST(CaptureProtocol, StepListsFollowThePaper) {
  const auto& core = capture_steps(StepSet::Core);
  const std::vector<std::string> names = {"floor", "stature", "span", "crotch_height", "hip_breadth", "arm_length"};
  ASSERT_EQ(core.size(), names.size());
  for (size_t i = 0; i < names.size(); ++i) EXPECT_EQ(core[i].name, names[i]);
  const auto& all = capture_steps(StepSet::All);
  EXPECT_EQ(all.size(), 14u);  // floor + the paper's 13 candidates (§3.1.2)
  int heights = 0;
  for (const auto& s : all) {
    if (s.kind == StepKind::Height) ++heights;
    if (s.kind != StepKind::Floor) {
      const MeasurementInfo* info = find_measurement_info(s.name);
      ASSERT_TRUE(info) << s.name;
      EXPECT_TRUE(info->paper_13) << s.name;
    }
  }
  EXPECT_EQ(heights, 4);  // overall, nipple, navel, inseam
}

TEST(CaptureProfiles, BuiltinsCoverQuestAndViveAndJsonOverrides) {
  ProfileRegistry r = ProfileRegistry::builtin();
  for (const char* id : {"oculus-touch-v3", "meta-quest-touch-plus", "htc-vive"}) EXPECT_TRUE(r.find(id)) << id;
  EXPECT_TRUE(r.find(r.default_id()));
  EXPECT_EQ(r.first_known({"no-such-thing", "htc-vive", "oculus-touch-v3"}), "htc-vive");
  EXPECT_EQ(r.first_known({"no-such-thing"}), "");
  r.merge_json(R"({"default": "my-wand", "profiles": {"my-wand": {"tip_offset_m": [0, 0.01, 0.08]}, "htc-vive": {"tip_offset_m": [0, 0, 0.075]}}})");
  EXPECT_EQ(r.default_id(), "my-wand");
  EXPECT_DOUBLE_EQ(r.find("my-wand")->tip_offset.z(), 0.08);
  EXPECT_DOUBLE_EQ(r.find("htc-vive")->tip_offset.z(), 0.075);
  try {
    r.merge_json(R"({"profiles": {"bad": {"tip_offset_m": [0, 0, 2]}}})");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "profiles.bad.tip_offset_m");
  }
  EXPECT_FALSE(r.find("bad"));
  EXPECT_THROW(r.merge_json("{not json"), Error);
  EXPECT_THROW(r.merge_json(R"({"default": "nope", "profiles": {}})"), Error);
  EXPECT_EQ(r.default_id(), "my-wand");
}

}  // namespace
}  // namespace caliper::capture
