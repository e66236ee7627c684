// Durable capture sessions: SQLite in WAL mode, one transaction per event (an accepted point, an
// undo, a redo, an entry), so a process killed mid-session loses nothing and a new process
// rebuilds the session from its stored points. sqlite3.h stays inside store.cpp.
#pragma once
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "caliper/capture/body_image_task.h"
#include "caliper/capture/protocol.h"

namespace caliper::capture {

struct StoredSession {
  std::string id;       // "s-…"
  std::string created;  // ISO 8601 UTC, "2026-11-21T18:00:00Z"
  std::string updated;
  Mode mode = Mode::Self;
  StepSet steps = StepSet::Core;
  std::string profile;
  std::optional<Sex> sex;
  std::optional<double> weight_kg;
  std::string state;                     // as last written (for listings)
  std::map<std::string, double> values;  // the measurement set as last written (cm, kg)
  std::vector<CapturePoint> points;      // accepted, in order
  std::vector<CapturePoint> redo;        // undone, the next to redo last
};

// A session's pairing state: the code's verifier (PBKDF2, see service.h) and the wrong codes
// tried since that code was issued.
struct PairingRecord {
  std::string verifier;
  int failures = 0;
};

// What is written with every change, so listings and exports need no replay.
struct SessionSummary {
  std::string state;
  std::map<std::string, double> values;  // cm and kg by canonical name
};

class SessionStore {
 public:
  // Opens `path`, creating it (and its folder) when absent. Throws Error(Format) naming the path
  // when the file is not SQLite, is corrupt, or is another application's database (it is never
  // modified then), and Error(Io) when it cannot be opened or created. Older schemas are
  // upgraded in place, in one transaction: a schema-1 file gains the wrong-code counter (at 0),
  // schema 1 and 2 files the body-image tasks table (empty).
  explicit SessionStore(const std::string& path);
  ~SessionStore();
  SessionStore(const SessionStore&) = delete;
  SessionStore& operator=(const SessionStore&) = delete;

  // $XDG_DATA_HOME/caliper/sessions.db, else ~/.local/share/caliper/sessions.db.
  static std::string default_path();
  static std::string path_in(const std::string& data_dir);  // data_dir/sessions.db
  const std::string& path() const;

  void create(const StoredSession& session, const std::string& pairing_verifier);
  std::vector<std::string> ids() const;  // newest first
  std::optional<StoredSession> load(const std::string& id) const;
  std::optional<PairingRecord> pairing(const std::string& id) const;
  // One more wrong code for the session (one transaction); returns the new count.
  int add_pairing_failure(const std::string& id);
  // A new code's verifier; the failure count starts again at 0.
  void set_pairing(const std::string& id, const std::string& verifier);
  bool contains(const std::string& id) const;

  // Each is one transaction. Throws Error(Io) when the write fails.
  void append_point(const std::string& id, const CapturePoint& point, const SessionSummary& after);
  void undo_point(const std::string& id, const SessionSummary& after);  // last accepted → redo list
  void redo_point(const std::string& id, const SessionSummary& after);  // first of the redo list → back
  void set_entries(const std::string& id, std::optional<Sex> sex, std::optional<double> weight_kg, const SessionSummary& after);
  void set_profile(const std::string& id, const std::string& profile);
  bool remove(const std::string& id);

  // Body-image tasks (body_image_task.h), each change one transaction. add_task abandons the
  // session's running task in the same transaction; answer_task writes the answer and returns
  // false (changing nothing) unless the task exists and is running.
  void add_task(const std::string& session_id, const BodyImageTask& task);
  std::vector<BodyImageTask> tasks(const std::string& session_id) const;  // oldest first
  bool answer_task(const std::string& session_id, const std::string& task_id, const BodyImageAnswer& answer);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace caliper::capture
