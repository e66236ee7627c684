// Capture sessions as a service: the protocol engine (protocol.h) per session, persisted in a
// SessionStore (store.h) as it changes, with pairing codes (6 digits; stored as a PBKDF2-HMAC-
// SHA256 verifier; each session accepts a limited number of wrong codes in its lifetime, then
// refuses every code until a new one is issued). Thread-safe; what the server's /api/sessions
// endpoints and `caliper sessions` use.
#pragma once
#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "caliper/capture/body_image_task.h"
#include "caliper/capture/profiles.h"
#include "caliper/capture/protocol.h"
#include "caliper/capture/store.h"

namespace caliper::capture {

struct Session {
  std::string id;
  std::string created;
  std::string profile;
  CaptureProtocol protocol;
};

struct NewSession {
  Mode mode = Mode::Self;
  StepSet steps = StepSet::Core;
  std::optional<Sex> sex;
  std::optional<double> weight_kg;  // checked against the catalogue
  std::string profile;              // empty: the registry's default; unknown: Error naming "profile"
};

struct CaptureServiceOptions {
  std::string database;  // empty: SessionStore::default_path()
  ProfileRegistry profiles = ProfileRegistry::builtin();
  HoldOptions hold;
  // Wrong pairing codes a session accepts in its lifetime, from all clients together, before it
  // locks (docs/capture.md "Pairing": 10 guesses find a random code with probability 10^-5).
  int max_pairing_failures = 10;
  // Sessions kept live in memory (least recently used beyond it are dropped and rebuilt from the
  // store on their next use; a hold in progress in a dropped session is lost, never a point).
  std::size_t max_cached_sessions = 256;
  // Codes recently verified (session → code), so a paired device's requests skip PBKDF2.
  std::size_t max_verified_codes = 256;
};

enum class PairingStatus {
  Paired,     // the session's code
  WrongCode,  // counted against the session's budget
  Locked,     // the budget is spent: every code (the right one too) is refused until reissue_pairing
  Outdated,   // the stored verifier is of a format no longer accepted (a Caliper older than schema 2): reissue
  NoSession,
};

struct PairingCheck {
  PairingStatus status = PairingStatus::NoSession;
  int failures = 0;      // wrong codes since the code was issued (after this check)
  int max_failures = 0;  // the budget (CaptureServiceOptions::max_pairing_failures)
  // WrongCode: this code was counted now. A wrong code the session has already counted (a paired
  // device still sending the code replaced by reissue_pairing) is refused without counting
  // again: it tells a guesser nothing new.
  bool counted = false;
  bool paired() const { return status == PairingStatus::Paired; }
};

class CaptureService {
 public:
  // Opens the store (throws as SessionStore does).
  explicit CaptureService(CaptureServiceOptions options = {});
  ~CaptureService();
  CaptureService(const CaptureService&) = delete;
  CaptureService& operator=(const CaptureService&) = delete;

  struct Created {
    Session session;
    std::string pairing_code;  // 6 digits; only the creator learns it
  };
  Created create(const NewSession& request);

  std::vector<Session> list();                      // newest first
  std::optional<Session> find(const std::string& id);
  // Whether `code` is the session's pairing code. The verifier is PBKDF2 (about 0.1 s, one at a
  // time across sessions, so the budget is exact under concurrent guesses); a code verified
  // before is recognised from memory. A wrong code is counted in the store (survives restarts);
  // only distinct wrong codes count (the ones counted are remembered in memory, per code issued).
  PairingCheck check_pairing(const std::string& id, const std::string& code);
  // A new code for the session (the experimenter's desktop or `caliper sessions pair`): the old
  // one stops working and the failure count starts again. nullopt when there is no such session.
  std::optional<std::string> reissue_pairing(const std::string& id);

  // Sessions live in memory now (at most max_cached_sessions).
  std::size_t cached_session_count();

  struct FeedResult {
    Session session;
    std::vector<CaptureEvent> events;
  };
  // `profile`: a WebXR profile id (or several, most specific first); the first known one becomes
  // the session's; empty keeps the session's. None known: Error naming "profile".
  // Samples are validated first (Error naming the field, nothing changed).
  std::optional<FeedResult> feed(const std::string& id, const std::vector<ControllerSample>& samples,
                                 const std::vector<std::string>& profile = {});
  // nullopt when the session does not exist; `changed` tells whether there was anything to undo.
  std::optional<Session> undo(const std::string& id, bool* changed = nullptr);
  std::optional<Session> redo(const std::string& id, bool* changed = nullptr);
  std::optional<Session> set_entries(const std::string& id, std::optional<double> weight_kg, std::optional<Sex> sex);
  bool remove(const std::string& id);

  // Body-image tasks (body_image_task.h), stored with the session. nullopt: no such session.
  // start_task checks the task (Error naming the field) and abandons the running one.
  std::optional<BodyImageTask> start_task(const std::string& id, const NewBodyImageTask& task);
  std::optional<std::vector<BodyImageTask>> tasks(const std::string& id);
  enum class AnswerStatus { Answered, NoSession, NoTask, NotRunning, NotAdjustable };
  struct AnswerResult {
    AnswerStatus status = AnswerStatus::NoSession;
    std::optional<BodyImageTask> task;  // as stored after the call (absent for NoSession, NoTask)
  };
  // Answers a running adjust task: checks the answer (Error naming the field), adds the chosen
  // weight and BMI from the session's values and the server time, and returns only after the
  // answer is committed. A show task takes no answer (NotAdjustable).
  AnswerResult answer_task(const std::string& id, const std::string& task_id, BodyImageAnswer answer);

  const ProfileRegistry& profiles() const { return options_.profiles; }
  const std::string& database_path() const;

 private:
  std::optional<Session> step(const std::string& id, bool* changed, bool forward);  // undo / redo
  Session* live(const std::string& id);  // cached or loaded from the store; nullptr if absent
  std::unique_ptr<Session> load(const std::string& id) const;  // rebuilt from the store, not cached
  void forget(const std::string& id);  // drops the live session and its verified code
  CaptureServiceOptions options_;
  std::unique_ptr<SessionStore> store_;
  std::mutex mutex_;         // the caches and the store
  std::mutex verify_mutex_;  // one PBKDF2 verification (or re-issue) at a time
  // Live sessions (holds in progress are here only) and verified codes, both LRU-bounded.
  struct Caches;
  std::unique_ptr<Caches> caches_;
};

}  // namespace caliper::capture
