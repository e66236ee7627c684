// Capture sessions: protocol engines kept live in memory, every change written to the store in
// the same call (one transaction per event), sessions rebuilt from their stored points.
#include "caliper/capture/service.h"

#include <algorithm>
#include <cmath>
#include <ctime>

#include "caliper/errors.h"
#include "caliper/detail/lru_cache.h"
#include "pairing_verifier.h"
#include "utc_time.h"

namespace caliper::capture {

namespace {

using detail::now_iso;

// Session ids: public handles (listed to the desktop), from the OS's entropy source.
std::string random_id() { return "s-" + detail::random_hex_bytes(6); }

bool equal_constant_time(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

SessionSummary summary_of(const CaptureProtocol& p) { return {to_string(p.state()), p.measurement_set()}; }

}  // namespace

struct CaptureService::Caches {
  caliper::detail::LruCache<std::string, std::unique_ptr<Session>> sessions;
  // session → (its code, the verifier it matched): a verifier changed by another process
  // (`caliper sessions pair`) makes the entry stale.
  caliper::detail::LruCache<std::string, std::pair<std::string, std::string>> verified;
  // session → (the verifier, the wrong codes counted against it): at most the budget per session.
  caliper::detail::LruCache<std::string, std::pair<std::string, std::vector<std::string>>> wrong;
  Caches(std::size_t s, std::size_t v)
      : sessions(std::max<std::size_t>(1, s)), verified(std::max<std::size_t>(1, v)), wrong(std::max<std::size_t>(1, v)) {}
};

CaptureService::CaptureService(CaptureServiceOptions options)
    : options_(std::move(options)), caches_(std::make_unique<Caches>(options_.max_cached_sessions, options_.max_verified_codes)) {
  if (options_.max_pairing_failures < 1)
    throw Error(ErrorKind::InvalidArgument, "max_pairing_failures must be at least 1", "max_pairing_failures");
  const std::string path = options_.database.empty() ? SessionStore::default_path() : options_.database;
  store_ = std::make_unique<SessionStore>(path);
}

CaptureService::~CaptureService() = default;

const std::string& CaptureService::database_path() const { return store_->path(); }

std::unique_ptr<Session> CaptureService::load(const std::string& id) const {
  std::optional<StoredSession> stored = store_->load(id);
  if (!stored) return nullptr;
  CaptureProtocol::Config config;
  config.mode = stored->mode;
  config.steps = stored->steps;
  config.hold = options_.hold;
  auto s = std::make_unique<Session>(Session{stored->id, stored->created, stored->profile, CaptureProtocol(config)});
  s->protocol.restore(std::move(stored->points), std::move(stored->redo));
  if (stored->sex) s->protocol.set_sex(*stored->sex);
  if (stored->weight_kg) s->protocol.set_weight_kg(*stored->weight_kg);
  return s;
}

Session* CaptureService::live(const std::string& id) {
  if (std::unique_ptr<Session>* cached = caches_->sessions.find(id)) {
    // Another process (`caliper sessions delete`) may have removed it from the store since.
    if (store_->contains(id)) return cached->get();
    forget(id);
    return nullptr;
  }
  std::unique_ptr<Session> s = load(id);
  if (!s) return nullptr;
  return caches_->sessions.insert(id, std::move(s)).get();
}

void CaptureService::forget(const std::string& id) {
  caches_->sessions.erase(id);
  caches_->verified.erase(id);
  caches_->wrong.erase(id);
}

std::size_t CaptureService::cached_session_count() {
  std::lock_guard<std::mutex> lock(mutex_);
  return caches_->sessions.size();
}

CaptureService::Created CaptureService::create(const NewSession& r) {
  std::string profile = r.profile.empty() ? options_.profiles.default_id() : r.profile;
  if (!options_.profiles.find(profile))
    throw Error(ErrorKind::InvalidArgument, "unknown controller profile '" + profile + "' (GET /api/capture/profiles lists them)", "profile");
  CaptureProtocol::Config config;
  config.mode = r.mode;
  config.steps = r.steps;
  config.hold = options_.hold;
  CaptureProtocol protocol(config);
  if (r.sex) protocol.set_sex(*r.sex);
  if (r.weight_kg) protocol.set_weight_kg(*r.weight_kg);

  Created out{Session{random_id(), now_iso(), profile, protocol}, detail::random_decimal_digits(6)};
  const std::string verifier = detail::make_pairing_verifier(out.pairing_code);  // PBKDF2: outside the lock
  std::lock_guard<std::mutex> lock(mutex_);
  StoredSession ss;
  ss.id = out.session.id;
  ss.created = out.session.created;
  ss.mode = r.mode;
  ss.steps = r.steps;
  ss.profile = profile;
  ss.sex = protocol.sex();
  ss.weight_kg = protocol.weight_kg();
  ss.state = to_string(protocol.state());
  ss.values = protocol.measurement_set();
  store_->create(ss, verifier);
  caches_->sessions.insert(ss.id, std::make_unique<Session>(out.session));
  caches_->verified.insert(ss.id, {out.pairing_code, verifier});
  return out;
}

std::vector<Session> CaptureService::list() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<Session> out;
  // Sessions not live are rebuilt for the listing only: listing many sessions does not evict
  // the ones in use.
  for (const auto& id : store_->ids()) {
    if (std::unique_ptr<Session>* cached = caches_->sessions.peek(id)) out.push_back(**cached);
    else if (std::unique_ptr<Session> s = load(id)) out.push_back(*s);
  }
  return out;
}

std::optional<Session> CaptureService::find(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Session* s = live(id);
  if (!s) return std::nullopt;
  return *s;
}

PairingCheck CaptureService::check_pairing(const std::string& id, const std::string& code) {
  PairingCheck out;
  out.max_failures = options_.max_pairing_failures;
  // Known without PBKDF2: no session, a spent budget, an outdated verifier, a code verified before.
  auto quick = [&]() -> bool {
    const std::optional<PairingRecord> rec = store_->pairing(id);
    if (!rec) {
      out.status = PairingStatus::NoSession;
      return true;
    }
    out.failures = rec->failures;
    if (rec->failures >= options_.max_pairing_failures) {
      out.status = PairingStatus::Locked;
      caches_->verified.erase(id);
      return true;
    }
    if (const auto* known = caches_->verified.find(id);
        known && known->second == rec->verifier && equal_constant_time(known->first, code)) {
      out.status = PairingStatus::Paired;
      return true;
    }
    if (const auto* tried = caches_->wrong.find(id); tried && tried->first == rec->verifier)
      for (const std::string& w : tried->second)
        if (equal_constant_time(w, code)) {
          out.status = PairingStatus::WrongCode;
          return true;
        }
    return false;
  };
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (quick()) return out;
  }
  // One verification at a time: every wrong code is counted before the next one is tried, so
  // concurrent guesses cannot overshoot the budget. The session lock is not held meanwhile, so
  // paired devices (verified from memory) are not slowed down by guessers.
  std::lock_guard<std::mutex> verifying(verify_mutex_);
  std::string verifier;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (quick()) return out;
    verifier = store_->pairing(id)->verifier;
  }
  const detail::VerifierMatch match = detail::match_pairing_verifier(verifier, code);
  std::lock_guard<std::mutex> lock(mutex_);
  switch (match) {
    case detail::VerifierMatch::Match:
      out.status = PairingStatus::Paired;
      caches_->verified.insert(id, {code, verifier});
      break;
    case detail::VerifierMatch::Unsupported:
      out.status = PairingStatus::Outdated;
      break;
    case detail::VerifierMatch::Mismatch: {
      out.status = PairingStatus::WrongCode;
      out.counted = true;
      out.failures = store_->add_pairing_failure(id);
      auto* tried = caches_->wrong.find(id);
      if (!tried || tried->first != verifier) tried = &caches_->wrong.insert(id, {verifier, {}});
      tried->second.push_back(code);
      if (out.failures >= options_.max_pairing_failures) out.status = PairingStatus::Locked;
      break;
    }
  }
  return out;
}

std::optional<std::string> CaptureService::reissue_pairing(const std::string& id) {
  const std::string code = detail::random_decimal_digits(6);
  const std::string verifier = detail::make_pairing_verifier(code);
  std::lock_guard<std::mutex> verifying(verify_mutex_);  // no verification of the old code runs across it
  std::lock_guard<std::mutex> lock(mutex_);
  if (!store_->contains(id)) return std::nullopt;
  store_->set_pairing(id, verifier);
  caches_->verified.insert(id, {code, verifier});
  caches_->wrong.erase(id);
  return code;
}

std::optional<CaptureService::FeedResult> CaptureService::feed(const std::string& id, const std::vector<ControllerSample>& samples,
                                                               const std::vector<std::string>& profile) {
  validate_samples(samples);
  std::lock_guard<std::mutex> lock(mutex_);
  Session* s = live(id);
  if (!s) return std::nullopt;
  if (!profile.empty()) {
    const std::string known = options_.profiles.first_known(profile);
    if (known.empty())
      throw Error(ErrorKind::InvalidArgument,
                  "unknown controller profile '" + profile.front() + "' (GET /api/capture/profiles lists them)", "profile");
    if (known != s->profile) {
      store_->set_profile(id, known);
      s->profile = known;
    }
  }
  const Eigen::Vector3d offset = options_.profiles.find(s->profile) ? options_.profiles.find(s->profile)->tip_offset
                                                                    : Eigen::Vector3d::Zero();
  // Points are written one by one as the engine accepts them; a failed write leaves the engine
  // as the store has it (rebuilt from the store), never ahead of it.
  CaptureProtocol before = s->protocol;
  FeedResult out{*s, s->protocol.feed(samples, offset)};
  if (s->protocol.points().size() != before.points().size()) {
    try {
      CaptureProtocol replay = before;
      for (const auto& e : out.events) {
        if (e.type != EventType::PointAccepted || !e.point) continue;
        replay.restore([&] { auto p = replay.points(); p.push_back(*e.point); return p; }(), {});
        store_->append_point(id, *e.point, summary_of(replay));
      }
    } catch (...) {
      caches_->sessions.erase(id);
      throw;
    }
  }
  out.session = *s;
  return out;
}

std::optional<Session> CaptureService::undo(const std::string& id, bool* changed) { return step(id, changed, false); }
std::optional<Session> CaptureService::redo(const std::string& id, bool* changed) { return step(id, changed, true); }

std::optional<Session> CaptureService::step(const std::string& id, bool* changed, bool forward) {
  std::lock_guard<std::mutex> lock(mutex_);
  Session* s = live(id);
  if (!s) return std::nullopt;
  const bool did = forward ? s->protocol.redo() : s->protocol.undo();
  if (changed) *changed = did;
  if (did) {
    try {
      if (forward) store_->redo_point(id, summary_of(s->protocol));
      else store_->undo_point(id, summary_of(s->protocol));
    } catch (...) {
      caches_->sessions.erase(id);  // memory and store disagree now: reload from the store next time
      throw;
    }
  }
  return *s;
}

std::optional<Session> CaptureService::set_entries(const std::string& id, std::optional<double> weight_kg, std::optional<Sex> sex) {
  std::lock_guard<std::mutex> lock(mutex_);
  Session* s = live(id);
  if (!s) return std::nullopt;
  CaptureProtocol next = s->protocol;  // both entries checked before either is kept
  if (weight_kg) next.set_weight_kg(*weight_kg);
  if (sex) next.set_sex(*sex);
  store_->set_entries(id, next.sex(), next.weight_kg(), summary_of(next));
  s->protocol = std::move(next);
  return *s;
}

bool CaptureService::remove(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  forget(id);
  return store_->remove(id);
}

std::optional<BodyImageTask> CaptureService::start_task(const std::string& id, const NewBodyImageTask& n) {
  check_new_task(n);
  std::lock_guard<std::mutex> lock(mutex_);
  if (!live(id)) return std::nullopt;
  BodyImageTask t;
  t.id = "t-" + detail::random_hex_bytes(6);
  t.kind = n.kind;
  t.instruction = n.instruction;
  t.start_weight_change_pct = n.start_weight_change_pct;
  t.range_min_pct = n.range_min_pct;
  t.range_max_pct = n.range_max_pct;
  t.state = TaskState::Running;
  t.created = now_iso();
  store_->add_task(id, t);
  return t;
}

std::optional<std::vector<BodyImageTask>> CaptureService::tasks(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!live(id)) return std::nullopt;
  return store_->tasks(id);
}

CaptureService::AnswerResult CaptureService::answer_task(const std::string& id, const std::string& task_id, BodyImageAnswer answer) {
  std::lock_guard<std::mutex> lock(mutex_);
  AnswerResult out;
  Session* s = live(id);
  if (!s) return out;
  const auto find_task = [&]() -> std::optional<BodyImageTask> {
    for (auto& t : store_->tasks(id))
      if (t.id == task_id) return t;
    return std::nullopt;
  };
  out.task = find_task();
  if (!out.task) {
    out.status = AnswerStatus::NoTask;
    return out;
  }
  if (out.task->state != TaskState::Running) {
    out.status = AnswerStatus::NotRunning;
    return out;
  }
  if (out.task->kind != TaskKind::Adjust) {
    out.status = AnswerStatus::NotAdjustable;
    return out;
  }
  check_answer(*out.task, answer);
  // What the chosen change means for the person as measured (the set is in cm and kg).
  const std::map<std::string, double> values = s->protocol.measurement_set();
  answer.chosen_weight_kg.reset();
  answer.chosen_bmi.reset();
  if (auto w = values.find("weight"); w != values.end()) {
    answer.chosen_weight_kg = w->second * (1 + answer.chosen_weight_change_pct / 100);
    if (auto h = values.find("stature"); h != values.end() && h->second > 0)
      answer.chosen_bmi = *answer.chosen_weight_kg / std::pow(h->second / 100, 2);
  }
  answer.answered = now_iso();
  out.status = store_->answer_task(id, task_id, answer) ? AnswerStatus::Answered : AnswerStatus::NotRunning;
  out.task = find_task();
  return out;
}

}  // namespace caliper::capture
