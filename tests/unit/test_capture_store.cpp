// Capture storage and sessions: SQLite durability (a process killed mid-session resumes with
// the same values), undo/redo across processes, pairing codes never stored in clear, corrupt and
// foreign files refused and left untouched, the default data path and measurement-set files.
// How pairing codes are verified and locked: test_capture_pairing.cpp.
#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>

#include "caliper/capture/measurement_set.h"
#include "caliper/capture/service.h"
#include "caliper/errors.h"
#include "temp_files.h"
#include "test_capture_script.h"

namespace caliper::capture {
namespace {

using test::SampleScript;
using test::ScriptedPerson;
using test::service_options;
using test::TempDir;

const Eigen::Vector3d kTouchPlus = ProfileRegistry::builtin().find("meta-quest-touch-plus")->tip_offset;

void feed_script(CaptureService& svc, const std::string& id, SampleScript& s) {
  for (const auto& b : s.batches()) ASSERT_TRUE(svc.feed(id, b, {"meta-quest-touch-plus"}));
}

// A child process measures half a session and is killed (SIGKILL: no destructor, no close);
// a new service on the same file resumes and finishes. The result equals an uninterrupted run.
TEST(CaptureStore, ASessionKilledMidwayResumesWithTheSameValues) {
  TempDir dir;
  const std::string db = dir / "sessions.db";
  ScriptedPerson person;
  std::string id, code;
  {
    CaptureService svc(service_options(db));
    auto c = svc.create({Mode::Self, StepSet::Core, Sex::Male, std::nullopt, ""});
    id = c.session.id;
    code = c.pairing_code;
  }
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    CaptureService svc(service_options(db));
    SampleScript s(kTouchPlus, 21);
    test::script_floor(s, person);
    for (int rep = 0; rep < 2; ++rep) s.hold(1, person.head_top, 1.2);
    s.hold(0, person.left_fingertip, 1.2, &person.right_fingertip);  // first span repetition
    s.tip[1] = person.head_top;  // and a hold in progress when the process dies
    s.trigger[1] = 1;
    s.run(0.5);
    for (const auto& b : s.batches()) svc.feed(id, b, {});
    kill(getpid(), SIGKILL);
  }
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL);

  CaptureService resumed(service_options(db));
  auto s0 = resumed.find(id);
  ASSERT_TRUE(s0);
  EXPECT_EQ(s0->protocol.points().size(), 8u);  // 5 floor taps, 2 statures, 1 span
  ASSERT_TRUE(s0->protocol.current_step());
  EXPECT_EQ(s0->protocol.current_step()->spec.name, "span");
  EXPECT_EQ(s0->protocol.current_step()->repetition, 2);
  EXPECT_TRUE(resumed.check_pairing(id, code).paired());
  SampleScript rest(kTouchPlus, 22);
  rest.hold(0, person.left_fingertip, 1.2, &person.right_fingertip);
  for (int rep = 0; rep < 2; ++rep) rest.hold(1, person.crotch, 1.2);
  for (int rep = 0; rep < 2; ++rep) rest.hold(1, person.hip_right, 1.2, &person.hip_left);
  for (int rep = 0; rep < 2; ++rep) rest.hold(0, person.wrist, 1.2, &person.acromion);
  feed_script(resumed, id, rest);
  auto done = resumed.set_entries(id, 80.0, std::nullopt);
  ASSERT_TRUE(done);
  EXPECT_EQ(done->protocol.state(), SessionState::Done);
  const auto set = done->protocol.measurement_set();
  EXPECT_NEAR(set.at("stature"), person.stature() * 100, 0.25);
  EXPECT_NEAR(set.at("span"), person.span() * 100, 0.1);
  EXPECT_NEAR(set.at("crotch_height"), person.crotch_height() * 100, 0.25);
  EXPECT_NEAR(set.at("hip_breadth"), person.hip_breadth() * 100, 0.1);
  EXPECT_NEAR(set.at("arm_length"), person.arm_length() * 100, 0.1);
  EXPECT_DOUBLE_EQ(set.at("weight"), 80.0);

  // The values written with each event are what the engine has; a third process agrees.
  SessionStore store(db);
  auto stored = store.load(id);
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored->state, "done");
  ASSERT_EQ(stored->values.size(), set.size());
  for (const auto& [k, v] : set) EXPECT_DOUBLE_EQ(stored->values.at(k), v) << k;
  CaptureService third(service_options(db));
  EXPECT_EQ(third.find(id)->protocol.measurement_set(), set);
}

TEST(CaptureStore, UndoAndRedoSurviveARestart) {
  TempDir dir;
  const std::string db = dir / "sessions.db";
  ScriptedPerson person;
  std::string id;
  {
    CaptureService svc(service_options(db));
    id = svc.create({}).session.id;
    SampleScript s(kTouchPlus, 4);
    test::script_floor(s, person);
    feed_script(svc, id, s);
    bool changed = false;
    ASSERT_TRUE(svc.undo(id, &changed));
    EXPECT_TRUE(changed);
    svc.undo(id);
  }
  {
    CaptureService svc(service_options(db));
    auto s = svc.find(id);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->protocol.points().size(), 3u);
    EXPECT_EQ(s->protocol.redo_points().size(), 2u);
    svc.redo(id);
  }
  CaptureService svc(service_options(db));
  auto s = svc.find(id);
  EXPECT_EQ(s->protocol.points().size(), 4u);
  EXPECT_EQ(s->protocol.redo_points().size(), 1u);
  bool changed = true;
  svc.redo(id, &changed);
  EXPECT_TRUE(changed);
  svc.redo(id, &changed);
  EXPECT_FALSE(changed);
  EXPECT_TRUE(svc.find(id)->protocol.floor_m());
}

TEST(CaptureStore, PairingCodesAreSixDigitsCheckedAndNeverStoredInClear) {
  TempDir dir;
  const std::string db = dir / "sessions.db";
  std::string id, code;
  {
    CaptureService svc(service_options(db));
    auto c = svc.create({});
    id = c.session.id;
    code = c.pairing_code;
    ASSERT_EQ(code.size(), 6u);
    EXPECT_EQ(code.find_first_not_of("0123456789"), std::string::npos);
    EXPECT_TRUE(svc.check_pairing(id, code).paired());
    std::string wrong = code;
    wrong[0] = wrong[0] == '9' ? '0' : static_cast<char>(wrong[0] + 1);
    EXPECT_EQ(svc.check_pairing(id, wrong).status, PairingStatus::WrongCode);
    EXPECT_EQ(svc.check_pairing(id, "").status, PairingStatus::WrongCode);
    EXPECT_EQ(svc.check_pairing("s-nope", code).status, PairingStatus::NoSession);
    auto other = svc.create({});
    EXPECT_NE(other.session.id, id);
  }
  SessionStore store(db);
  const auto h = store.pairing(id);
  ASSERT_TRUE(h);
  EXPECT_EQ(h->verifier.find(code), std::string::npos);
  EXPECT_EQ(h->verifier.rfind("pbkdf2-sha256$", 0), 0u);
  EXPECT_EQ(h->failures, 2);  // the two wrong codes above
}

TEST(CaptureStore, CorruptAndForeignFilesAreRefusedAndLeftUntouched) {
  TempDir dir;
  const std::string garbage = dir / "garbage.db";
  const std::string text = std::string("this is not a database at all, but somebody's notes\n") + std::string(5000, 'x');
  test::write_file(garbage, text);
  try {
    SessionStore s(garbage);
    FAIL() << "opened a text file";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Format);
    EXPECT_NE(std::string(e.what()).find("not a Caliper sessions database"), std::string::npos) << e.what();
  }
  EXPECT_EQ(test::read_file(garbage), text);

  const std::string foreign = dir / "foreign.db";
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(foreign.c_str(), &db), SQLITE_OK);
  sqlite3_exec(db, "CREATE TABLE recipes (name TEXT); INSERT INTO recipes VALUES ('soup');", nullptr, nullptr, nullptr);
  sqlite3_close(db);
  const std::string before = test::read_file(foreign);
  try {
    CaptureService svc(service_options(foreign));
    FAIL() << "opened another application's database";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), ErrorKind::Format);
    EXPECT_NE(std::string(e.what()).find("another application"), std::string::npos) << e.what();
  }
  EXPECT_EQ(test::read_file(foreign), before);

  // A Caliper file whose pages were damaged after the header.
  const std::string damaged = dir / "damaged.db";
  {
    CaptureService svc(service_options(damaged));
    for (int i = 0; i < 30; ++i) svc.create({});
  }
  std::string bytes = test::read_file(damaged);
  ASSERT_GT(bytes.size(), 8192u);
  for (size_t i = 4096; i < bytes.size(); ++i) bytes[i] = static_cast<char>(i * 7);
  test::write_file(damaged, bytes);
  EXPECT_THROW(SessionStore s(damaged), Error);
  EXPECT_EQ(test::read_file(damaged), bytes);
}

mode_t mode_of(const std::string& path) {
  struct stat st {};
  EXPECT_EQ(::stat(path.c_str(), &st), 0) << path;
  return st.st_mode & 07777;
}

// Audit (docs/reliability.md): sessions.db and its -wal/-shm files were created 0644 (anyone on
// the machine could read everyone's measurements). Now the folder the store creates is 0700 and
// the files 0600, whatever the umask, and files an older Caliper left 0644 are tightened.
TEST(CaptureStore, TheDatabaseItsWalFilesAndTheirFolderAreOwnerOnly) {
  TempDir dir;
  const mode_t old_mask = ::umask(022);
  const std::string data = dir / "new-data-folder";
  const std::string db = SessionStore::path_in(data);
  {
    CaptureService svc(service_options(db));
    svc.create({});  // a write: SQLite creates the -wal and -shm files
    EXPECT_EQ(mode_of(data), 0700u);
    for (const std::string& f : {db, db + "-wal", db + "-shm"}) EXPECT_EQ(mode_of(f), 0600u) << f;
  }
  ASSERT_EQ(::chmod(db.c_str(), 0644), 0);
  {
    CaptureService svc(service_options(db));
    svc.create({});
    for (const std::string& f : {db, db + "-wal", db + "-shm"}) EXPECT_EQ(mode_of(f), 0600u) << f;
  }
  ::umask(old_mask);
}

TEST(CaptureStore, DefaultPathFollowsXdgDataHome) {
  const char* old_xdg = std::getenv("XDG_DATA_HOME");
  const std::string saved = old_xdg ? old_xdg : "";
  setenv("XDG_DATA_HOME", "/tmp/xdg-test", 1);
  EXPECT_EQ(SessionStore::default_path(), "/tmp/xdg-test/caliper/sessions.db");
  unsetenv("XDG_DATA_HOME");
  const char* home = std::getenv("HOME");
  if (home) {
    EXPECT_EQ(SessionStore::default_path(), std::string(home) + "/.local/share/caliper/sessions.db");
  }
  if (old_xdg) setenv("XDG_DATA_HOME", saved.c_str(), 1);
  EXPECT_EQ(SessionStore::path_in("/data/x"), "/data/x/sessions.db");
}

TEST(CaptureService, ListsNewestFirstAndDeletes) {
  TempDir dir;
  CaptureService svc(service_options(dir / "s.db"));
  const std::string a = svc.create({}).session.id;
  const std::string b = svc.create({Mode::Other, StepSet::All, Sex::Female, 55.0, "htc-vive"}).session.id;
  auto list = svc.list();
  ASSERT_EQ(list.size(), 2u);
  std::vector<std::string> ids = {list[0].id, list[1].id};
  EXPECT_NE(std::find(ids.begin(), ids.end(), a), ids.end());
  auto sb = svc.find(b);
  EXPECT_EQ(sb->profile, "htc-vive");
  EXPECT_EQ(sb->protocol.steps_total(), 14);
  EXPECT_EQ(*sb->protocol.weight_kg(), 55.0);
  EXPECT_TRUE(svc.remove(a));
  EXPECT_FALSE(svc.remove(a));
  EXPECT_FALSE(svc.find(a));
  EXPECT_EQ(svc.list().size(), 1u);
  EXPECT_THROW(svc.create({Mode::Self, StepSet::Core, std::nullopt, std::nullopt, "no-such-controller"}), Error);
  EXPECT_THROW(svc.create({Mode::Self, StepSet::Core, std::nullopt, 3000.0, ""}), Error);
  EXPECT_THROW(svc.set_entries(b, std::nan(""), std::nullopt), Error);
  EXPECT_EQ(*svc.find(b)->protocol.weight_kg(), 55.0);  // a refused entry changes nothing
}

// `caliper sessions delete` runs in another process while a server holds the session in memory:
// the server must not go on serving it, nor write points for it.
TEST(CaptureService, ASessionDeletedByAnotherProcessIsGone) {
  TempDir dir;
  CaptureService server(service_options(dir / "s.db"));
  const std::string id = server.create({}).session.id;
  ASSERT_TRUE(server.find(id));
  {
    CaptureService other(service_options(dir / "s.db"));
    EXPECT_TRUE(other.remove(id));
  }
  EXPECT_FALSE(server.find(id));
  EXPECT_FALSE(server.feed(id, {}, {}));
  EXPECT_FALSE(server.undo(id, nullptr));
  EXPECT_FALSE(server.set_entries(id, 60.0, std::nullopt));
  EXPECT_TRUE(server.list().empty());
  EXPECT_FALSE(SessionStore(dir / "s.db").contains(id));
}

TEST(MeasurementSetFile, RoundTripsJsonAndCsvAndChecksValues) {
  MeasurementSetFile set;
  set.sex = Sex::Female;
  set.edge = {{"stature", 172.34}, {"weight", 61.5}, {"hip_breadth", 35.2}};
  for (Sex sex : {Sex::Female, Sex::Male, Sex::Neutral}) {  // neutral too: the server writes it
    set.sex = sex;
    for (const std::string& text : {write_measurement_set_json(set), write_measurement_set_csv(set)}) {
      const MeasurementSetFile back = parse_measurement_set(text);
      EXPECT_EQ(back.sex, set.sex) << text;
      EXPECT_EQ(back.edge, set.edge) << text;
    }
  }
  set.sex = Sex::Female;
  EXPECT_NE(write_measurement_set_json(set).find("\"format\": \"caliper-measurements\""), std::string::npos);
  const MeasurementSetFile csv = parse_measurement_set("measurement,value,unit\nheight,1.72,m\nspan,1700,mm\nweight,132.27735731092,lb\n");
  EXPECT_DOUBLE_EQ(csv.edge.at("stature"), 172.0);
  EXPECT_DOUBLE_EQ(csv.edge.at("span"), 170.0);
  EXPECT_NEAR(csv.edge.at("weight"), 60.0, 1e-9);
  EXPECT_FALSE(csv.sex);
  try {
    parse_measurement_set("{\"measurements\": {\"stature\": 900}}");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "stature");
  }
  EXPECT_THROW(parse_measurement_set("stature,abc\n"), Error);
  EXPECT_THROW(parse_measurement_set("{\"sex\": \"robot\", \"measurements\": {\"stature\": 170}}"), Error);
  EXPECT_THROW(parse_measurement_set("{\"version\": 99, \"measurements\": {\"stature\": 170}}"), Error);
  EXPECT_THROW(parse_measurement_set("{\"measurements\": {\"stature\": 1e999}}"), Error);
  try {
    parse_measurement_set("[1, 2, 3]");
    FAIL() << "a JSON array was read";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("expected a JSON object"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_measurement_set("{\"measurements\": {}}"), Error);
  EXPECT_THROW(parse_measurement_set("{\"measurements\": {\"elbow_wobble\": 3}}"), Error);
}

// The one reader serves the server too: the model a set was made on survives both formats, and
// a Caliper report reads as the values that were requested (achieved-only entries were no input).
TEST(MeasurementSetFile, KeepsTheModelAndReadsReports) {
  MeasurementSetFile set;
  set.model = "makehuman";
  set.edge = {{"stature", 180.0}};
  for (const std::string& text : {write_measurement_set_json(set), write_measurement_set_csv(set)})
    EXPECT_EQ(parse_measurement_set(text).model, std::optional<std::string>("makehuman")) << text;
  EXPECT_FALSE(parse_measurement_set("{\"measurements\": {\"stature\": 170}}").model);
  const MeasurementSetFile report = parse_measurement_set(R"({"measurements": {
      "stature": {"requested_cm": 171.5, "achieved_cm": 171.49},
      "weight": {"requested_kg": 66, "achieved_kg": 65.98},
      "chest_circumference": {"achieved_cm": 95.1}}})");
  EXPECT_EQ(report.edge, (std::map<std::string, double>{{"stature", 171.5}, {"weight", 66.0}}));
  try {
    parse_measurement_set(R"({"measurements": {"stature": {"height": 170}}})");
    FAIL() << "an object that is not a report entry was read";
  } catch (const Error& e) {
    EXPECT_EQ(e.field(), "stature");
  }
  EXPECT_THROW(parse_measurement_set(R"({"measurements": {"stature": {"requested_cm": "tall"}}})"), Error);
}

}  // namespace
}  // namespace caliper::capture
