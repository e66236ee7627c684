// Capture sessions: protocol engines kept live in memory, every change written to the store in
// the same call (one transaction per event), sessions rebuilt from their stored points.
#include "caliper/capture/service.h"

#include <ctime>
#include <random>

#include "caliper/errors.h"
#include "sha256.h"
#include "utc_time.h"

namespace caliper::capture {

namespace {

using detail::now_iso;

// Identifiers and codes come from the OS's entropy source: they guard who may write.
std::string random_digits(int n, std::random_device& rd) {
  std::uniform_int_distribution<int> digit(0, 9);
  std::string s;
  for (int i = 0; i < n; ++i) s += static_cast<char>('0' + digit(rd));
  return s;
}

std::string random_hex(int n, std::random_device& rd) {
  static const char* hex = "0123456789abcdef";
  std::uniform_int_distribution<int> nibble(0, 15);
  std::string s;
  for (int i = 0; i < n; ++i) s += hex[nibble(rd)];
  return s;
}

// "salt$sha256(salt + code)"
std::string hash_code(const std::string& code, const std::string& salt) { return salt + "$" + detail::sha256_hex(salt + code); }

bool equal_constant_time(const std::string& a, const std::string& b) {
  if (a.size() != b.size()) return false;
  unsigned char diff = 0;
  for (size_t i = 0; i < a.size(); ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

SessionSummary summary_of(const CaptureProtocol& p) { return {to_string(p.state()), p.measurement_set()}; }

}  // namespace

CaptureService::CaptureService(CaptureServiceOptions options) : options_(std::move(options)) {
  const std::string path = options_.database.empty() ? SessionStore::default_path() : options_.database;
  store_ = std::make_unique<SessionStore>(path);
}

CaptureService::~CaptureService() = default;

const std::string& CaptureService::database_path() const { return store_->path(); }

Session* CaptureService::live(const std::string& id) {
  auto it = sessions_.find(id);
  if (it != sessions_.end()) {
    // Another process (`caliper sessions delete`) may have removed it from the store since.
    if (store_->contains(id)) return it->second.get();
    sessions_.erase(it);
    return nullptr;
  }
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
  Session* raw = s.get();
  sessions_[id] = std::move(s);
  return raw;
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

  std::lock_guard<std::mutex> lock(mutex_);
  std::random_device rd;
  Created out{Session{"s-" + random_hex(12, rd), now_iso(), profile, protocol}, random_digits(6, rd)};
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
  store_->create(ss, hash_code(out.pairing_code, random_hex(16, rd)));
  sessions_[ss.id] = std::make_unique<Session>(out.session);
  return out;
}

std::vector<Session> CaptureService::list() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<Session> out;
  for (const auto& id : store_->ids())
    if (Session* s = live(id)) out.push_back(*s);
  return out;
}

std::optional<Session> CaptureService::find(const std::string& id) {
  std::lock_guard<std::mutex> lock(mutex_);
  Session* s = live(id);
  if (!s) return std::nullopt;
  return *s;
}

bool CaptureService::check_pairing(const std::string& id, const std::string& code) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::optional<std::string> stored = store_->pairing_hash(id);
  if (!stored) return false;
  const size_t dollar = stored->find('$');
  if (dollar == std::string::npos) return false;
  return equal_constant_time(hash_code(code, stored->substr(0, dollar)), *stored);
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
      sessions_.erase(id);
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
      sessions_.erase(id);  // memory and store disagree now: reload from the store next time
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
  sessions_.erase(id);
  return store_->remove(id);
}

}  // namespace caliper::capture
