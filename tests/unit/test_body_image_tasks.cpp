// Body-image tasks stored with a capture session (capture/body_image_task.h): one running task
// at a time, an answer only for the running adjust task and only once, the chosen weight from
// the session's own values, everything kept by a new service on the same file, a schema-2
// database upgraded in place, a newer one refused untouched, and the CSV export's cells.
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <string>
#include <utility>
#include <vector>

#include "caliper/capture/body_image_task.h"
#include "caliper/capture/service.h"
#include "caliper/errors.h"
#include "fixtures.h"
#include "temp_files.h"
#include "test_capture_script.h"

namespace caliper::capture {
namespace {

using test::service_options;
using test::TempDir;
using Status = CaptureService::AnswerStatus;

BodyImageAnswer answer_of(double pct) {
  BodyImageAnswer a;
  a.chosen_weight_change_pct = pct;
  a.shown_at_s = 2;
  a.answered_at_s = 9.5;
  a.adjustments = 3;
  return a;
}

long long user_version(const std::string& db) {
  sqlite3* h = nullptr;
  EXPECT_EQ(sqlite3_open(db.c_str(), &h), SQLITE_OK);
  sqlite3_stmt* q = nullptr;
  sqlite3_prepare_v2(h, "PRAGMA user_version", -1, &q, nullptr);
  sqlite3_step(q);
  const long long v = sqlite3_column_int64(q, 0);
  sqlite3_finalize(q);
  sqlite3_close(h);
  return v;
}

void run_sql(const std::string& db, const std::string& sql) {
  sqlite3* h = nullptr;
  ASSERT_EQ(sqlite3_open(db.c_str(), &h), SQLITE_OK);
  char* err = nullptr;
  EXPECT_EQ(sqlite3_exec(h, sql.c_str(), nullptr, nullptr, &err), SQLITE_OK) << (err ? err : "");
  sqlite3_free(err);
  sqlite3_close(h);
}

}  // namespace

TEST(BodyImageTasks, OneRunningTaskAnsweredOnceAndKeptAcrossAServiceRestart) {
  TempDir dir;
  const std::string db = dir / "sessions.db";
  std::string id, adjust_id;
  {
    CaptureService svc(service_options(db));
    NewSession n;
    n.weight_kg = 64;
    id = svc.create(n).session.id;
    NewBodyImageTask show;
    show.kind = TaskKind::Show;
    show.start_weight_change_pct = 10;
    const auto shown = svc.start_task(id, show);
    ASSERT_TRUE(shown);
    EXPECT_EQ(svc.answer_task(id, shown->id, answer_of(0)).status, Status::NotAdjustable);
    const auto adjust = svc.start_task(id, NewBodyImageTask{});
    ASSERT_TRUE(adjust);
    adjust_id = adjust->id;
    EXPECT_NE(adjust_id, shown->id);
    // The show task was abandoned by the new one and takes no answer now either.
    EXPECT_EQ(svc.answer_task(id, shown->id, answer_of(0)).status, Status::NotRunning);
    EXPECT_EQ(svc.answer_task(id, "t-nope", answer_of(0)).status, Status::NoTask);
    EXPECT_EQ(svc.answer_task("s-nope", adjust_id, answer_of(0)).status, Status::NoSession);
    EXPECT_FALSE(svc.start_task("s-nope", NewBodyImageTask{}));
    // A bad answer changes nothing.
    EXPECT_THROW(svc.answer_task(id, adjust_id, answer_of(31)), Error);
    const auto r = svc.answer_task(id, adjust_id, answer_of(-12.5));
    ASSERT_EQ(r.status, Status::Answered);
    ASSERT_TRUE(r.task && r.task->answer);
    EXPECT_EQ(r.task->state, TaskState::Answered);
    // 64 kg entered, no stature measured yet: the weight, no BMI.
    ASSERT_TRUE(r.task->answer->chosen_weight_kg);
    EXPECT_DOUBLE_EQ(*r.task->answer->chosen_weight_kg, 56.0);
    EXPECT_FALSE(r.task->answer->chosen_bmi);
    EXPECT_EQ(svc.answer_task(id, adjust_id, answer_of(5)).status, Status::NotRunning);
  }
  CaptureService again(service_options(db));
  const auto tasks = again.tasks(id);
  ASSERT_TRUE(tasks);
  ASSERT_EQ(tasks->size(), 2u);
  EXPECT_EQ((*tasks)[0].kind, TaskKind::Show);
  EXPECT_EQ((*tasks)[0].state, TaskState::Abandoned);
  EXPECT_EQ((*tasks)[0].start_weight_change_pct, 10);
  EXPECT_EQ((*tasks)[1].id, adjust_id);
  ASSERT_TRUE((*tasks)[1].answer);
  EXPECT_EQ((*tasks)[1].answer->chosen_weight_change_pct, -12.5);
  EXPECT_EQ((*tasks)[1].answer->shown_at_s, 2);
  EXPECT_EQ((*tasks)[1].answer->answered_at_s, 9.5);
  EXPECT_EQ((*tasks)[1].answer->adjustments, 3);
  EXPECT_EQ((*tasks)[1].instruction, kHowILook);
  // Deleting the session deletes its tasks.
  EXPECT_TRUE(again.remove(id));
  EXPECT_FALSE(again.tasks(id));
}

TEST(BodyImageTasks, ASchema2DatabaseGainsTheTableAndANewerOneIsRefused) {
  TempDir dir;
  const std::string db = dir / "sessions.db";
  std::string id;
  {
    CaptureService svc(service_options(db));
    id = svc.create({}).session.id;
  }
  EXPECT_EQ(user_version(db), 3);
  run_sql(db, "DROP TABLE body_image_tasks; PRAGMA user_version = 2;");
  {
    CaptureService svc(service_options(db));
    ASSERT_TRUE(svc.find(id));
    ASSERT_TRUE(svc.start_task(id, NewBodyImageTask{}));
    EXPECT_EQ(svc.tasks(id)->size(), 1u);
  }
  EXPECT_EQ(user_version(db), 3);
  run_sql(db, "PRAGMA user_version = 4;");
  const Error e = test::catch_error([&] { CaptureService svc(service_options(db)); });
  EXPECT_EQ(e.kind(), ErrorKind::Format);
  EXPECT_NE(std::string(e.what()).find("schema version 4"), std::string::npos) << e.what();
  EXPECT_EQ(user_version(db), 4);  // left untouched
}

TEST(BodyImageTasks, ChecksNameTheField) {
  auto field_of = [](const NewBodyImageTask& t) { return test::catch_error([&] { check_new_task(t); }).field(); };
  NewBodyImageTask t;
  EXPECT_NO_THROW(check_new_task(t));
  t.instruction = "";
  EXPECT_EQ(field_of(t), "instruction");
  t.instruction = std::string(201, 'x');
  EXPECT_EQ(field_of(t), "instruction");
  t.instruction = std::string(200, 'x');
  EXPECT_NO_THROW(check_new_task(t));
  t.instruction = "\xC3\xA4" + std::string(199, 'x');  // 200 code points, 201 bytes
  EXPECT_NO_THROW(check_new_task(t));
  t.instruction = "bad \xC3";
  EXPECT_EQ(field_of(t), "instruction");
  t.instruction = "tab\there";
  EXPECT_EQ(field_of(t), "instruction");
  t = {};
  t.range_min_pct = 10;
  t.range_max_pct = 10;
  EXPECT_EQ(field_of(t), "range_pct");
  t.range_min_pct = -51;
  EXPECT_EQ(field_of(t), "range_pct");
  t = {};
  t.start_weight_change_pct = 31;
  EXPECT_EQ(field_of(t), "start_weight_change_pct");
  t.start_weight_change_pct = std::nan("");
  EXPECT_EQ(field_of(t), "start_weight_change_pct");
  EXPECT_EQ(test::catch_error([] { parse_task_kind("watch"); }).field(), "kind");
}

TEST(BodyImageTasks, CsvCellsAreQuotedWhenTheyNeedIt) {
  BodyImageTask t;
  t.id = "t-1";
  t.instruction = "say \"thin\", or not";
  t.created = "2026-11-25T16:00:00Z";
  const std::string csv = write_body_image_tasks_csv({t});
  EXPECT_EQ(csv.substr(csv.find('\n') + 1),
            "t-1,adjust,\"say \"\"thin\"\", or not\",0,-30,30,running,2026-11-25T16:00:00Z,,,,,,,\n");
}

// An instruction is free text typed by whoever holds the desktop; opened in a spreadsheet, a
// cell starting with = + - @ would run as a formula. The export keeps the text, defused.
TEST(BodyImageTasks, CsvTextThatLooksLikeAFormulaIsNotOne) {
  BodyImageTask t;
  t.id = "t-2";
  t.created = "2026-11-25T16:00:00Z";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"=HYPERLINK(\"http://x\",\"y\")", "\"'=HYPERLINK(\"\"http://x\"\",\"\"y\"\")\""},
      {"+1 looks thinner", "'+1 looks thinner"},
      {"-20% please", "'-20% please"},
      {"@SUM(A1)", "'@SUM(A1)"},
      {"how I look = fine", "how I look = fine"},  // only the first character matters
  };
  for (const auto& [instruction, cell] : cases) {
    t.instruction = instruction;
    const std::string csv = write_body_image_tasks_csv({t});
    EXPECT_EQ(csv.substr(csv.find('\n') + 1), "t-2,adjust," + cell + ",0,-30,30,running,2026-11-25T16:00:00Z,,,,,,,\n")
        << instruction;
  }
}

}  // namespace caliper::capture
