// SQLite storage of capture sessions (WAL, one transaction per event). The file carries
// PRAGMA application_id = 'Cali' so a foreign database is recognised and left alone.
#include "caliper/capture/store.h"

#include <sqlite3.h>

#include <cstdlib>
#include <filesystem>

#include "caliper/errors.h"
#include "caliper/private_files.h"
#include "utc_time.h"

namespace caliper::capture {

namespace {

constexpr int kApplicationId = 0x43616C69;  // "Cali"
// 2: sessions.pairing_failures, wrong pairing codes since the code was issued;
// pairing_hash holds a PBKDF2 verifier. Version 1 files are migrated when opened (their SHA-256
// verifiers stay and are refused at pairing until the experimenter re-issues a code).
// 3: body_image_tasks, the virtual mirror's tasks and their answers (capture/body_image_task.h);
// version 1 and 2 files gain the table when opened.
constexpr int kSchemaVersion = 3;

const char* kSchema = R"sql(
CREATE TABLE sessions (
  id TEXT PRIMARY KEY,
  created TEXT NOT NULL,
  updated TEXT NOT NULL,
  mode TEXT NOT NULL,
  steps TEXT NOT NULL,
  profile TEXT NOT NULL,
  pairing_hash TEXT NOT NULL,
  pairing_failures INTEGER NOT NULL DEFAULT 0,
  sex TEXT,
  weight_kg REAL,
  state TEXT NOT NULL
);
CREATE TABLE points (
  session_id TEXT NOT NULL REFERENCES sessions(id) ON DELETE CASCADE,
  seq INTEGER NOT NULL,
  undone INTEGER NOT NULL DEFAULT 0,
  step TEXT NOT NULL,
  repetition INTEGER NOT NULL,
  value_m REAL NOT NULL,
  hand TEXT NOT NULL,
  tip_x REAL, tip_y REAL, tip_z REAL,
  other_x REAL, other_y REAL, other_z REAL,
  t_start REAL, t_end REAL,
  written TEXT NOT NULL,
  PRIMARY KEY (session_id, seq)
);
CREATE TABLE measurement_values (
  session_id TEXT NOT NULL REFERENCES sessions(id) ON DELETE CASCADE,
  name TEXT NOT NULL,
  value REAL NOT NULL,
  PRIMARY KEY (session_id, name)
);
)sql";

// Added in schema 3 (created with a new file, or by the upgrade of an older one).
const char* kTasksSchema = R"sql(
CREATE TABLE body_image_tasks (
  session_id TEXT NOT NULL REFERENCES sessions(id) ON DELETE CASCADE,
  id TEXT NOT NULL,
  seq INTEGER NOT NULL,
  kind TEXT NOT NULL,
  instruction TEXT NOT NULL,
  start_weight_change_pct REAL NOT NULL,
  range_min_pct REAL NOT NULL,
  range_max_pct REAL NOT NULL,
  state TEXT NOT NULL,
  created TEXT NOT NULL,
  chosen_weight_change_pct REAL,
  chosen_weight_kg REAL,
  chosen_bmi REAL,
  shown_at_s REAL,
  answered_at_s REAL,
  adjustments INTEGER,
  answered TEXT,
  PRIMARY KEY (session_id, id)
);
)sql";

using detail::now_iso;

// A prepared statement that finalises itself.
class Stmt {
 public:
  Stmt(sqlite3* db, const char* sql) : db_(db) {
    if (sqlite3_prepare_v2(db, sql, -1, &s_, nullptr) != SQLITE_OK)
      throw Error(ErrorKind::Io, std::string("sessions database: ") + sqlite3_errmsg(db), "database");
  }
  ~Stmt() { sqlite3_finalize(s_); }
  Stmt(const Stmt&) = delete;
  Stmt& operator=(const Stmt&) = delete;
  Stmt& bind(int i, const std::string& v) {
    sqlite3_bind_text(s_, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT);
    return *this;
  }
  Stmt& bind(int i, double v) {
    sqlite3_bind_double(s_, i, v);
    return *this;
  }
  Stmt& bind_int(int i, long long v) {
    sqlite3_bind_int64(s_, i, v);
    return *this;
  }
  Stmt& bind_null(int i) {
    sqlite3_bind_null(s_, i);
    return *this;
  }
  bool step() {  // true while a row is available
    const int rc = sqlite3_step(s_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    throw Error(rc == SQLITE_NOTADB || rc == SQLITE_CORRUPT ? ErrorKind::Format : ErrorKind::Io,
                std::string("sessions database: ") + sqlite3_errmsg(db_), "database");
  }
  std::string text(int c) const {
    const unsigned char* t = sqlite3_column_text(s_, c);
    return t ? reinterpret_cast<const char*>(t) : "";
  }
  double real(int c) const { return sqlite3_column_double(s_, c); }
  long long integer(int c) const { return sqlite3_column_int64(s_, c); }
  bool null(int c) const { return sqlite3_column_type(s_, c) == SQLITE_NULL; }

 private:
  sqlite3* db_;
  sqlite3_stmt* s_ = nullptr;
};

CapturePoint read_point(const Stmt& q, int c0) {
  CapturePoint p;
  p.step = q.text(c0);
  p.repetition = static_cast<int>(q.integer(c0 + 1));
  p.value_m = q.real(c0 + 2);
  p.hand = q.text(c0 + 3) == "left" ? Hand::Left : Hand::Right;
  p.tip = {q.real(c0 + 4), q.real(c0 + 5), q.real(c0 + 6)};
  p.other_tip = {q.real(c0 + 7), q.real(c0 + 8), q.real(c0 + 9)};
  p.t_start = q.real(c0 + 10);
  p.t_end = q.real(c0 + 11);
  return p;
}

}  // namespace

struct SessionStore::Impl {
  std::string path;
  sqlite3* db = nullptr;

  void exec(const char* sql) {
    char* err = nullptr;
    const int rc = sqlite3_exec(db, sql, nullptr, nullptr, &err);
    if (rc != SQLITE_OK) {
      const std::string msg = err ? err : sqlite3_errstr(rc);
      sqlite3_free(err);
      throw Error(rc == SQLITE_NOTADB || rc == SQLITE_CORRUPT ? ErrorKind::Format : ErrorKind::Io,
                  "sessions database '" + path + "': " + msg, "database");
    }
  }

  long long pragma_int(const char* sql) {
    Stmt q(db, sql);
    return q.step() ? q.integer(0) : 0;
  }

  // Runs `body` in one transaction (IMMEDIATE: the write lock is taken up front).
  template <class F>
  void transaction(F&& body) {
    exec("BEGIN IMMEDIATE");
    try {
      body();
      exec("COMMIT");
    } catch (...) {
      sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
      throw;
    }
  }

  void write_summary(const std::string& id, const SessionSummary& s) {
    Stmt(db, "UPDATE sessions SET state = ?1, updated = ?2 WHERE id = ?3").bind(1, s.state).bind(2, now_iso()).bind(3, id).step();
    Stmt(db, "DELETE FROM measurement_values WHERE session_id = ?1").bind(1, id).step();
    for (const auto& [name, value] : s.values)
      Stmt(db, "INSERT INTO measurement_values (session_id, name, value) VALUES (?1, ?2, ?3)").bind(1, id).bind(2, name).bind(3, value).step();
  }
};

SessionStore::SessionStore(const std::string& path) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  s.path = path;
  namespace fs = std::filesystem;
  std::error_code ec;
  create_private_directory(fs::path(path).parent_path().string());
  if (fs::is_directory(path, ec)) throw Error(ErrorKind::Io, "sessions database '" + path + "' is a folder", "database");
  // Owner-only before SQLite opens it: the -wal and -shm files SQLite creates take the
  // database's mode; ones left by an older Caliper are tightened too.
  create_private_file(path);
  for (const char* suffix : {"-wal", "-shm"}) restrict_to_owner(path + suffix);
  if (sqlite3_open_v2(path.c_str(), &s.db, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_FULLMUTEX, nullptr) != SQLITE_OK) {
    const std::string msg = s.db ? sqlite3_errmsg(s.db) : "out of memory";
    sqlite3_close(s.db);
    s.db = nullptr;
    throw Error(ErrorKind::Io, "cannot open sessions database '" + path + "': " + msg, "database");
  }
  try {
    sqlite3_busy_timeout(s.db, 5000);
    // Read before anything is written: a file that is not ours must stay untouched.
    long long app_id = 0, tables = 0;
    try {
      app_id = s.pragma_int("PRAGMA application_id");
      tables = s.pragma_int("SELECT count(*) FROM sqlite_master");
    } catch (const Error&) {
      throw Error(ErrorKind::Format, "'" + path + "' is not a Caliper sessions database (not SQLite, or corrupt); it was left untouched",
                  "database");
    }
    if (app_id != kApplicationId && !(app_id == 0 && tables == 0))
      throw Error(ErrorKind::Format,
                  "'" + path + "' is another application's SQLite database, not Caliper's sessions; it was left untouched",
                  "database");
    if (app_id == kApplicationId) {
      Stmt q(s.db, "PRAGMA quick_check");
      const std::string verdict = q.step() ? q.text(0) : "";
      if (verdict != "ok")
        throw Error(ErrorKind::Format, "sessions database '" + path + "' is corrupt (" + verdict + "); it was left untouched", "database");
      const long long version = s.pragma_int("PRAGMA user_version");
      if (version < 1 || version > kSchemaVersion)
        throw Error(ErrorKind::Format,
                    "sessions database '" + path + "' has schema version " + std::to_string(version) + "; this Caliper reads versions 1 to " +
                        std::to_string(kSchemaVersion),
                    "database");
    }
    s.exec("PRAGMA journal_mode = WAL");
    s.exec("PRAGMA synchronous = FULL");  // a committed event survives a power cut, not only a kill
    s.exec("PRAGMA foreign_keys = ON");
    if (app_id == kApplicationId && s.pragma_int("PRAGMA user_version") < kSchemaVersion) {
      // One transaction from whatever version the file has to the current one.
      s.transaction([&] {
        const long long from = s.pragma_int("PRAGMA user_version");
        if (from < 2) s.exec("ALTER TABLE sessions ADD COLUMN pairing_failures INTEGER NOT NULL DEFAULT 0");
        if (from < 3) s.exec(kTasksSchema);
        s.exec(("PRAGMA user_version = " + std::to_string(kSchemaVersion)).c_str());
      });
    }
    if (app_id == 0) {
      s.transaction([&] {
        s.exec(kSchema);
        s.exec(kTasksSchema);
        s.exec(("PRAGMA application_id = " + std::to_string(kApplicationId)).c_str());
        s.exec(("PRAGMA user_version = " + std::to_string(kSchemaVersion)).c_str());
      });
    }
  } catch (...) {
    sqlite3_close(s.db);
    s.db = nullptr;
    throw;
  }
}

SessionStore::~SessionStore() {
  if (impl_ && impl_->db) sqlite3_close(impl_->db);
}

std::string SessionStore::default_path() {
  const char* xdg = std::getenv("XDG_DATA_HOME");
  if (xdg && *xdg == '/') return path_in(std::string(xdg) + "/caliper");
  const char* home = std::getenv("HOME");
  if (!home || !*home) throw Error(ErrorKind::Io, "neither $XDG_DATA_HOME nor $HOME is set; give a data folder (--data)", "--data");
  return path_in(std::string(home) + "/.local/share/caliper");
}

std::string SessionStore::path_in(const std::string& data_dir) { return (std::filesystem::path(data_dir) / "sessions.db").string(); }

const std::string& SessionStore::path() const { return impl_->path; }

void SessionStore::create(const StoredSession& ss, const std::string& pairing_hash) {
  Impl& s = *impl_;
  s.transaction([&] {
    Stmt q(s.db,
           "INSERT INTO sessions (id, created, updated, mode, steps, profile, pairing_hash, sex, weight_kg, state) "
           "VALUES (?1, ?2, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)");
    q.bind(1, ss.id).bind(2, ss.created).bind(3, to_string(ss.mode)).bind(4, to_string(ss.steps)).bind(5, ss.profile).bind(6, pairing_hash);
    if (ss.sex) q.bind(7, to_string(*ss.sex));
    else q.bind_null(7);
    if (ss.weight_kg) q.bind(8, *ss.weight_kg);
    else q.bind_null(8);
    q.bind(9, ss.state);
    q.step();
    s.write_summary(ss.id, {ss.state, ss.values});
  });
}

std::vector<std::string> SessionStore::ids() const {
  Stmt q(impl_->db, "SELECT id FROM sessions ORDER BY created DESC, rowid DESC");
  std::vector<std::string> out;
  while (q.step()) out.push_back(q.text(0));
  return out;
}

std::optional<StoredSession> SessionStore::load(const std::string& id) const {
  sqlite3* db = impl_->db;
  StoredSession ss;
  {
    Stmt q(db, "SELECT id, created, updated, mode, steps, profile, sex, weight_kg, state FROM sessions WHERE id = ?1");
    q.bind(1, id);
    if (!q.step()) return std::nullopt;
    ss.id = q.text(0);
    ss.created = q.text(1);
    ss.updated = q.text(2);
    try {
      ss.mode = parse_mode(q.text(3));
      ss.steps = parse_step_set(q.text(4));
      if (!q.null(6)) ss.sex = parse_sex(q.text(6));
    } catch (const Error& e) {
      throw Error(ErrorKind::Format, "sessions database: session " + id + " is damaged: " + e.what(), "database");
    }
    ss.profile = q.text(5);
    if (!q.null(7)) ss.weight_kg = q.real(7);
    ss.state = q.text(8);
  }
  const char* cols = "SELECT step, repetition, value_m, hand, tip_x, tip_y, tip_z, other_x, other_y, other_z, t_start, t_end FROM points ";
  {
    Stmt q(db, (std::string(cols) + "WHERE session_id = ?1 AND undone = 0 ORDER BY seq").c_str());
    q.bind(1, id);
    while (q.step()) ss.points.push_back(read_point(q, 0));
  }
  {
    Stmt q(db, (std::string(cols) + "WHERE session_id = ?1 AND undone = 1 ORDER BY seq DESC").c_str());
    q.bind(1, id);
    while (q.step()) ss.redo.push_back(read_point(q, 0));
  }
  {
    Stmt q(db, "SELECT name, value FROM measurement_values WHERE session_id = ?1");
    q.bind(1, id);
    while (q.step()) ss.values[q.text(0)] = q.real(1);
  }
  return ss;
}

std::optional<PairingRecord> SessionStore::pairing(const std::string& id) const {
  Stmt q(impl_->db, "SELECT pairing_hash, pairing_failures FROM sessions WHERE id = ?1");
  q.bind(1, id);
  if (!q.step()) return std::nullopt;
  return PairingRecord{q.text(0), static_cast<int>(q.integer(1))};
}

int SessionStore::add_pairing_failure(const std::string& id) {
  Impl& s = *impl_;
  int failures = 0;
  s.transaction([&] {
    Stmt(s.db, "UPDATE sessions SET pairing_failures = pairing_failures + 1 WHERE id = ?1").bind(1, id).step();
    Stmt q(s.db, "SELECT pairing_failures FROM sessions WHERE id = ?1");
    q.bind(1, id);
    if (q.step()) failures = static_cast<int>(q.integer(0));
  });
  return failures;
}

void SessionStore::set_pairing(const std::string& id, const std::string& verifier) {
  Impl& s = *impl_;
  s.transaction([&] {
    Stmt(s.db, "UPDATE sessions SET pairing_hash = ?1, pairing_failures = 0 WHERE id = ?2").bind(1, verifier).bind(2, id).step();
  });
}

bool SessionStore::contains(const std::string& id) const {
  Stmt q(impl_->db, "SELECT 1 FROM sessions WHERE id = ?1");
  q.bind(1, id);
  return q.step();
}

void SessionStore::append_point(const std::string& id, const CapturePoint& p, const SessionSummary& after) {
  Impl& s = *impl_;
  s.transaction([&] {
    // A new point ends what could be redone.
    Stmt(s.db, "DELETE FROM points WHERE session_id = ?1 AND undone = 1").bind(1, id).step();
    Stmt q(s.db,
           "INSERT INTO points (session_id, seq, step, repetition, value_m, hand, tip_x, tip_y, tip_z, other_x, other_y, other_z, "
           "t_start, t_end, written) VALUES (?1, (SELECT coalesce(max(seq), 0) + 1 FROM points WHERE session_id = ?1), ?2, ?3, ?4, "
           "?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14)");
    q.bind(1, id).bind(2, p.step).bind_int(3, p.repetition).bind(4, p.value_m).bind(5, to_string(p.hand));
    q.bind(6, p.tip.x()).bind(7, p.tip.y()).bind(8, p.tip.z()).bind(9, p.other_tip.x()).bind(10, p.other_tip.y()).bind(11, p.other_tip.z());
    q.bind(12, p.t_start).bind(13, p.t_end).bind(14, now_iso());
    q.step();
    s.write_summary(id, after);
  });
}

void SessionStore::undo_point(const std::string& id, const SessionSummary& after) {
  Impl& s = *impl_;
  s.transaction([&] {
    Stmt(s.db,
         "UPDATE points SET undone = 1 WHERE session_id = ?1 AND seq = (SELECT max(seq) FROM points WHERE session_id = ?1 AND undone = 0)")
        .bind(1, id)
        .step();
    s.write_summary(id, after);
  });
}

void SessionStore::redo_point(const std::string& id, const SessionSummary& after) {
  Impl& s = *impl_;
  s.transaction([&] {
    Stmt(s.db,
         "UPDATE points SET undone = 0 WHERE session_id = ?1 AND seq = (SELECT min(seq) FROM points WHERE session_id = ?1 AND undone = 1)")
        .bind(1, id)
        .step();
    s.write_summary(id, after);
  });
}

void SessionStore::set_entries(const std::string& id, std::optional<Sex> sex, std::optional<double> weight_kg,
                               const SessionSummary& after) {
  Impl& s = *impl_;
  s.transaction([&] {
    Stmt q(s.db, "UPDATE sessions SET sex = ?1, weight_kg = ?2 WHERE id = ?3");
    if (sex) q.bind(1, to_string(*sex));
    else q.bind_null(1);
    if (weight_kg) q.bind(2, *weight_kg);
    else q.bind_null(2);
    q.bind(3, id);
    q.step();
    s.write_summary(id, after);
  });
}

void SessionStore::set_profile(const std::string& id, const std::string& profile) {
  Impl& s = *impl_;
  s.transaction([&] { Stmt(s.db, "UPDATE sessions SET profile = ?1 WHERE id = ?2").bind(1, profile).bind(2, id).step(); });
}

bool SessionStore::remove(const std::string& id) {
  Impl& s = *impl_;
  bool removed = false;
  s.transaction([&] {
    Stmt(s.db, "DELETE FROM points WHERE session_id = ?1").bind(1, id).step();
    Stmt(s.db, "DELETE FROM measurement_values WHERE session_id = ?1").bind(1, id).step();
    Stmt(s.db, "DELETE FROM body_image_tasks WHERE session_id = ?1").bind(1, id).step();
    Stmt(s.db, "DELETE FROM sessions WHERE id = ?1").bind(1, id).step();
    removed = sqlite3_changes(s.db) > 0;
  });
  return removed;
}

void SessionStore::add_task(const std::string& session_id, const BodyImageTask& t) {
  Impl& s = *impl_;
  s.transaction([&] {
    Stmt(s.db, "UPDATE body_image_tasks SET state = 'abandoned' WHERE session_id = ?1 AND state = 'running'").bind(1, session_id).step();
    Stmt q(s.db,
           "INSERT INTO body_image_tasks (session_id, id, seq, kind, instruction, start_weight_change_pct, range_min_pct, "
           "range_max_pct, state, created) VALUES (?1, ?2, (SELECT coalesce(max(seq), 0) + 1 FROM body_image_tasks WHERE "
           "session_id = ?1), ?3, ?4, ?5, ?6, ?7, ?8, ?9)");
    q.bind(1, session_id).bind(2, t.id).bind(3, to_string(t.kind)).bind(4, t.instruction).bind(5, t.start_weight_change_pct);
    q.bind(6, t.range_min_pct).bind(7, t.range_max_pct).bind(8, to_string(t.state)).bind(9, t.created);
    q.step();
  });
}

std::vector<BodyImageTask> SessionStore::tasks(const std::string& session_id) const {
  Stmt q(impl_->db,
         "SELECT id, kind, instruction, start_weight_change_pct, range_min_pct, range_max_pct, state, created, "
         "chosen_weight_change_pct, chosen_weight_kg, chosen_bmi, shown_at_s, answered_at_s, adjustments, answered "
         "FROM body_image_tasks WHERE session_id = ?1 ORDER BY seq");
  q.bind(1, session_id);
  std::vector<BodyImageTask> out;
  while (q.step()) {
    BodyImageTask t;
    t.id = q.text(0);
    try {
      t.kind = parse_task_kind(q.text(1));
      t.state = parse_task_state(q.text(6));
    } catch (const Error& e) {
      throw Error(ErrorKind::Format, "sessions database: a body-image task of session " + session_id + " is damaged: " + e.what(),
                  "database");
    }
    t.instruction = q.text(2);
    t.start_weight_change_pct = q.real(3);
    t.range_min_pct = q.real(4);
    t.range_max_pct = q.real(5);
    t.created = q.text(7);
    if (!q.null(14)) {
      BodyImageAnswer a;
      a.chosen_weight_change_pct = q.real(8);
      if (!q.null(9)) a.chosen_weight_kg = q.real(9);
      if (!q.null(10)) a.chosen_bmi = q.real(10);
      a.shown_at_s = q.real(11);
      a.answered_at_s = q.real(12);
      a.adjustments = static_cast<int>(q.integer(13));
      a.answered = q.text(14);
      t.answer = a;
    }
    out.push_back(std::move(t));
  }
  return out;
}

bool SessionStore::answer_task(const std::string& session_id, const std::string& task_id, const BodyImageAnswer& a) {
  Impl& s = *impl_;
  bool answered = false;
  s.transaction([&] {
    Stmt q(s.db,
           "UPDATE body_image_tasks SET state = 'answered', chosen_weight_change_pct = ?3, chosen_weight_kg = ?4, chosen_bmi = ?5, "
           "shown_at_s = ?6, answered_at_s = ?7, adjustments = ?8, answered = ?9 "
           "WHERE session_id = ?1 AND id = ?2 AND state = 'running'");
    q.bind(1, session_id).bind(2, task_id).bind(3, a.chosen_weight_change_pct);
    if (a.chosen_weight_kg) q.bind(4, *a.chosen_weight_kg);
    else q.bind_null(4);
    if (a.chosen_bmi) q.bind(5, *a.chosen_bmi);
    else q.bind_null(5);
    q.bind(6, a.shown_at_s).bind(7, a.answered_at_s).bind_int(8, a.adjustments).bind(9, a.answered);
    q.step();
    answered = sqlite3_changes(s.db) == 1;
  });
  return answered;
}

}  // namespace caliper::capture
