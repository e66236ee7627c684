// Whose input failed: errors start as the caller's; the code that opens one of the
// installation's files says so, and what is read later from such a model is blamed on it too.
// Every gate lets only caliper::Error out.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <new>

#include "caliper/caliper.h"
#include "fixtures.h"
#include "gate.h"
#include "temp_files.h"

namespace caliper {
namespace {

using test::TempDir;

// Points load_model's models folder at `dir` for the lifetime of the object.
struct ModelsDirOverride {
  std::string old;
  bool had = false;
  explicit ModelsDirOverride(const std::string& dir) {
    if (const char* v = std::getenv("CALIPER_MODELS_DIR")) had = true, old = v;
    ::setenv("CALIPER_MODELS_DIR", dir.c_str(), 1);
  }
  ~ModelsDirOverride() { had ? (void)::setenv("CALIPER_MODELS_DIR", old.c_str(), 1) : (void)::unsetenv("CALIPER_MODELS_DIR"); }
};

TEST(ErrorOrigin, ErrorsAreTheCallersUnlessTheOpenerSaysOtherwise) {
  const Error plain(ErrorKind::Format, "bad", "weights");
  EXPECT_EQ(plain.origin(), ErrorOrigin::Caller);
  const Error e = test::catch_error([] { installation_input([]() -> int { throw Error(ErrorKind::Format, "bad", "weights"); }); });
  EXPECT_TRUE(e.from_installation());
  EXPECT_EQ(e.kind(), ErrorKind::Format);
  EXPECT_EQ(e.field(), "weights");
  EXPECT_STREQ(e.what(), "bad");
  // Restating keeps kind and origin.
  const Error r = e.restated("--model: bad", "--model");
  EXPECT_TRUE(r.from_installation());
  EXPECT_EQ(r.kind(), ErrorKind::Format);
  EXPECT_EQ(r.field(), "--model");
  EXPECT_EQ(installation_input([] { return 7; }), 7);
}

TEST(ErrorOrigin, AModelFoundByNameIsTheInstallationsAndAPathTheCallers) {
  TempDir dir;
  test::write_file(dir / "broken-female.npz", "this is not a zip");
  ModelsDirOverride models(dir.path.string());
  const Error by_name = test::catch_error([] { load_model("broken", Sex::Female); });
  EXPECT_TRUE(by_name.from_installation()) << by_name.what();
  EXPECT_EQ(by_name.kind(), ErrorKind::Format);
  const Error by_path = test::catch_error([&] { load_model(dir / "broken-female.npz", Sex::Female); });
  EXPECT_EQ(by_path.origin(), ErrorOrigin::Caller) << by_path.what();
  // A name nothing answers to is the caller's mistake.
  EXPECT_EQ(test::catch_error([] { load_model("nobody", Sex::Female); }).origin(), ErrorOrigin::Caller);
  // And a good installed model is marked as the installation's.
  save_model(test::toy_model(), dir / "toy-female.npz");
  EXPECT_EQ(load_model("toy", Sex::Female).data().supplied_by, ErrorOrigin::Installation);
  EXPECT_EQ(load_model(dir / "toy-female.npz", Sex::Female).data().supplied_by, ErrorOrigin::Caller);
}

TEST(ErrorOrigin, BrokenMapsInsideAModelAreBlamedOnWhoeverSuppliedIt) {
  BodyModelData d = test::toy_model().data();
  d.metadata["real_to_virtual"] = R"({"format": "caliper-real-to-virtual", "maps": {"stature": {"slope": 1, "pairs": "20"}}})";
  for (ErrorOrigin origin : {ErrorOrigin::Caller, ErrorOrigin::Installation}) {
    auto model = std::make_shared<const BodyModel>(BodyModel(BodyModelData(d)).supplied_by(origin));
    const Error e = test::catch_error([&] { AvatarBuilder builder(model); });
    EXPECT_EQ(e.origin(), origin) << e.what();
    EXPECT_EQ(e.kind(), ErrorKind::Format);
    EXPECT_NE(std::string(e.what()).find("pairs"), std::string::npos) << e.what();
  }
}

TEST(Gate, OnlyTheLibrarysErrorsLeaveAGate) {
  // The reader's own error passes unchanged.
  const Error own = test::catch_error([] { gate("'f.npz'", "model", []() -> int { throw Error(ErrorKind::OutOfRange, "x", "stature"); }); });
  EXPECT_EQ(own.kind(), ErrorKind::OutOfRange);
  EXPECT_EQ(own.field(), "stature");
  // A bug's exception becomes a Format error naming the input.
  const Error bug = test::catch_error([] { gate("'f.npz'", "model", []() -> int { throw std::out_of_range("map::at"); }); });
  EXPECT_EQ(bug.kind(), ErrorKind::Format);
  EXPECT_EQ(bug.field(), "model");
  EXPECT_NE(std::string(bug.what()).find("'f.npz'"), std::string::npos);
  const Error memory = test::catch_error([] { gate("'f.npz'", "model", []() -> int { throw std::bad_alloc(); }); });
  EXPECT_EQ(memory.kind(), ErrorKind::Format);
  EXPECT_EQ(gate("x", "y", [] { return 3; }), 3);
}

}  // namespace
}  // namespace caliper
