// Capture sessions as a service: the protocol engine (protocol.h) per session, persisted in a
// SessionStore (store.h) as it changes, with pairing codes (6 digits, stored salted and hashed).
// Thread-safe; what the server's /api/sessions endpoints and `caliper sessions` use.
#pragma once
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

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
  // True when `code` is the session's pairing code (constant-time compare of the hashes).
  bool check_pairing(const std::string& id, const std::string& code);

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

  const ProfileRegistry& profiles() const { return options_.profiles; }
  const std::string& database_path() const;

 private:
  std::optional<Session> step(const std::string& id, bool* changed, bool forward);  // undo / redo
  Session* live(const std::string& id);  // cached or loaded from the store; nullptr if absent
  CaptureServiceOptions options_;
  std::unique_ptr<SessionStore> store_;
  std::mutex mutex_;
  std::map<std::string, std::unique_ptr<Session>> sessions_;  // live: holds in progress are here only
};

}  // namespace caliper::capture
