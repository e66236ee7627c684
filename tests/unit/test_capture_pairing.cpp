// Pairing codes (docs/reliability.md "Pairing codes"): the stored verifier is
// PBKDF2-HMAC-SHA256 of the code with a random salt (recomputed here with OpenSSL, independently
// of the library) and not a fast hash; every session has a budget of wrong codes that survives a
// restart and that concurrent guessers cannot overshoot; a locked session refuses the right code
// until a new one is issued; a verifier left by an older Caliper (salted SHA-256) is refused, not
// accepted, until a new code is issued; the live-session cache is bounded.
#include <gtest/gtest.h>
#include <openssl/evp.h>
#include <openssl/sha.h>
#include <sqlite3.h>

#include <atomic>
#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "caliper/capture/service.h"
#include "temp_files.h"
#include "test_capture_script.h"

namespace caliper::capture {
namespace {

using test::service_options;
using test::TempDir;

std::string hex(const unsigned char* b, size_t n) {
  static const char* d = "0123456789abcdef";
  std::string s;
  for (size_t i = 0; i < n; ++i) s += {d[b[i] >> 4], d[b[i] & 15]};
  return s;
}

std::vector<unsigned char> unhex(const std::string& h) {
  std::vector<unsigned char> out;
  for (size_t i = 0; i + 1 < h.size(); i += 2) out.push_back(static_cast<unsigned char>(std::stoi(h.substr(i, 2), nullptr, 16)));
  return out;
}

std::string sha256_hex(const std::string& data) {
  unsigned char md[SHA256_DIGEST_LENGTH];
  SHA256(reinterpret_cast<const unsigned char*>(data.data()), data.size(), md);
  return hex(md, sizeof md);
}

std::vector<std::string> split(const std::string& s, char c) {
  std::vector<std::string> out;
  size_t start = 0;
  for (size_t i; (i = s.find(c, start)) != std::string::npos; start = i + 1) out.push_back(s.substr(start, i - start));
  out.push_back(s.substr(start));
  return out;
}

std::string another_code(const std::string& code, int k) {
  std::string w = code;
  w[5] = static_cast<char>('0' + (code[5] - '0' + 1 + k % 9) % 10);
  w[4] = static_cast<char>('0' + (code[4] - '0' + k / 9) % 10);
  return w;
}

void exec_sql(sqlite3* db, const std::string& sql) {
  char* err = nullptr;
  ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &err), SQLITE_OK) << (err ? err : "") << "\n" << sql;
}

TEST(CapturePairing, TheVerifierIsPbkdf2OfTheCodeWithARandomSaltAndNotAFastHash) {
  TempDir dir;
  const std::string db = dir / "sessions.db";
  CaptureService svc(service_options(db));
  const auto a = svc.create({});
  const auto b = svc.create({});
  SessionStore store(db);
  const std::string va = store.pairing(a.session.id)->verifier, vb = store.pairing(b.session.id)->verifier;
  const auto parts = split(va, '$');
  ASSERT_EQ(parts.size(), 4u) << va;
  EXPECT_EQ(parts[0], "pbkdf2-sha256");
  EXPECT_EQ(parts[1], "200000");
  ASSERT_EQ(parts[2].size(), 32u);  // 16 random bytes
  ASSERT_EQ(parts[3].size(), 64u);
  EXPECT_NE(split(vb, '$')[2], parts[2]) << "every session has its own salt";

  // Recomputed with OpenSSL here: PBKDF2-HMAC-SHA256(code, salt bytes, 200000, 32 bytes).
  const std::vector<unsigned char> salt = unhex(parts[2]);
  unsigned char key[32];
  ASSERT_EQ(PKCS5_PBKDF2_HMAC(a.pairing_code.data(), 6, salt.data(), static_cast<int>(salt.size()), 200000, EVP_sha256(), 32, key), 1);
  EXPECT_EQ(hex(key, 32), parts[3]);
  // ... and none of the fast hashes an offline search would love.
  for (const std::string& fast : {sha256_hex(parts[2] + a.pairing_code), sha256_hex(a.pairing_code + parts[2]),
                                  sha256_hex(std::string(salt.begin(), salt.end()) + a.pairing_code), sha256_hex(a.pairing_code)})
    EXPECT_NE(fast, parts[3]);

  // Only the right code verifies; a fresh service (nothing remembered) takes the slow path, and
  // that path is slow: at least 5 ms per code here (measured ~60-130 ms; load only adds to it).
  CaptureService fresh(service_options(db));
  EXPECT_EQ(fresh.check_pairing(a.session.id, b.pairing_code == a.pairing_code ? another_code(a.pairing_code, 0) : b.pairing_code).status,
            PairingStatus::WrongCode);
  for (int k = 1; k < 4; ++k) EXPECT_EQ(fresh.check_pairing(a.session.id, another_code(a.pairing_code, k)).status, PairingStatus::WrongCode);
  EXPECT_EQ(fresh.check_pairing(a.session.id, a.pairing_code + "0").status, PairingStatus::WrongCode);
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_TRUE(fresh.check_pairing(a.session.id, a.pairing_code).paired());
  const double slow_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_GE(slow_ms, 5.0);
  // Once verified it is remembered: the next check is fast.
  const auto t1 = std::chrono::steady_clock::now();
  EXPECT_TRUE(fresh.check_pairing(a.session.id, a.pairing_code).paired());
  const double fast_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t1).count();
  EXPECT_LT(fast_ms, slow_ms);
  EXPECT_TRUE(fresh.check_pairing(b.session.id, b.pairing_code).paired());
}

TEST(CapturePairing, WrongCodesLockTheSessionAcrossARestartUntilANewCodeIsIssued) {
  TempDir dir;
  const std::string db = dir / "sessions.db";
  std::string id, code;
  {
    CaptureService svc(service_options(db));
    const auto c = svc.create({});
    id = c.session.id;
    code = c.pairing_code;
    const auto other = svc.create({});
    for (int k = 0; k < 6; ++k) {
      const PairingCheck r = svc.check_pairing(id, another_code(code, k));
      EXPECT_EQ(r.status, PairingStatus::WrongCode);
      EXPECT_EQ(r.failures, k + 1);
      EXPECT_EQ(r.max_failures, 10);
    }
    // The same wrong code again tells a guesser nothing: refused, not counted.
    for (int k = 0; k < 5; ++k) {
      const PairingCheck r = svc.check_pairing(id, another_code(code, 2));
      EXPECT_EQ(r.status, PairingStatus::WrongCode);
      EXPECT_FALSE(r.counted);
    }
    EXPECT_EQ(SessionStore(db).pairing(id)->failures, 6);
    // The right code still works before the budget is spent; it does not reset the count.
    EXPECT_TRUE(svc.check_pairing(id, code).paired());
    EXPECT_TRUE(svc.check_pairing(other.session.id, other.pairing_code).paired());
  }
  CaptureService svc(service_options(db));  // a restart keeps the count
  for (int k = 6; k < 9; ++k) EXPECT_EQ(svc.check_pairing(id, another_code(code, k)).status, PairingStatus::WrongCode);
  const PairingCheck tenth = svc.check_pairing(id, another_code(code, 9));
  EXPECT_EQ(tenth.status, PairingStatus::Locked);
  EXPECT_EQ(tenth.failures, 10);
  EXPECT_EQ(svc.check_pairing(id, code).status, PairingStatus::Locked) << "the right code after the lock";
  EXPECT_EQ(svc.check_pairing(id, another_code(code, 10)).status, PairingStatus::Locked);
  EXPECT_EQ(SessionStore(db).pairing(id)->failures, 10) << "refusals after the lock are not even tried";
  {
    CaptureService restarted(service_options(db));
    EXPECT_EQ(restarted.check_pairing(id, code).status, PairingStatus::Locked);
  }
  const std::optional<std::string> fresh = svc.reissue_pairing(id);
  ASSERT_TRUE(fresh);
  EXPECT_TRUE(svc.check_pairing(id, *fresh).paired());
  EXPECT_EQ(SessionStore(db).pairing(id)->failures, 0);
  if (*fresh != code) {
    // A paired device still sending the old code (polling twice a second) counts once, so it does
    // not lock the session again.
    for (int k = 0; k < 30; ++k) EXPECT_EQ(svc.check_pairing(id, code).status, PairingStatus::WrongCode) << "the old code is gone";
    EXPECT_EQ(SessionStore(db).pairing(id)->failures, 1);
    EXPECT_TRUE(svc.check_pairing(id, *fresh).paired());
  }
  EXPECT_FALSE(svc.reissue_pairing("s-nope"));
}

// Guessers in parallel (what rotating client addresses amounts to at this level): never more than
// the budget of codes is tried.
TEST(CapturePairing, ConcurrentGuessesCannotOvershootTheBudget) {
  TempDir dir;
  const std::string db = dir / "sessions.db";
  CaptureService svc(service_options(db));
  const auto c = svc.create({});
  std::atomic<int> wrong{0}, locked{0}, paired{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      for (int k = 0; k < 8; ++k) {
        std::string guess = another_code(c.pairing_code, (t * 8 + k) % 9);
        guess[3] = static_cast<char>('0' + (c.pairing_code[3] - '0' + 1 + t) % 10);  // never the code
        const PairingStatus s = svc.check_pairing(c.session.id, guess).status;
        (s == PairingStatus::WrongCode ? wrong : s == PairingStatus::Locked ? locked : paired)++;
      }
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(paired.load(), 0);
  EXPECT_EQ(wrong.load(), 9);    // the 10th wrong code is answered Locked
  EXPECT_EQ(locked.load(), 23);
  EXPECT_EQ(SessionStore(db).pairing(c.session.id)->failures, 10);
  EXPECT_EQ(svc.check_pairing(c.session.id, c.pairing_code).status, PairingStatus::Locked);
}

// A sessions.db written by an older Caliper: schema version 1 (no failure count) and the verifier
// "salt$SHA-256(salt + code)". It opens (migrated to the current version), its points are kept, and its
// code is refused as outdated — even the right one, which the old scheme would accept — without
// counting, until a new code is issued.
TEST(CapturePairing, AnOldSha256VerifierIsRefusedNotAcceptedUntilANewCodeIsIssued) {
  TempDir dir;
  const std::string db = dir / "sessions.db";
  test::ScriptedPerson person;
  std::string id;
  const std::string code = "482913", salt = "0123456789abcdef";
  {
    CaptureService svc(service_options(db));
    id = svc.create({}).session.id;
    test::SampleScript s(ProfileRegistry::builtin().find("meta-quest-touch-plus")->tip_offset, 7);
    test::script_floor(s, person);
    for (const auto& b : s.batches()) svc.feed(id, b, {});
  }
  {
    sqlite3* h = nullptr;
    ASSERT_EQ(sqlite3_open(db.c_str(), &h), SQLITE_OK);
    exec_sql(h, "ALTER TABLE sessions DROP COLUMN pairing_failures");
    exec_sql(h, "DROP TABLE body_image_tasks");  // schema 3's
    exec_sql(h, "UPDATE sessions SET pairing_hash = '" + salt + "$" + sha256_hex(salt + code) + "'");
    exec_sql(h, "PRAGMA user_version = 1");
    sqlite3_close(h);
  }
  CaptureService svc(service_options(db));
  ASSERT_TRUE(svc.find(id));
  EXPECT_EQ(svc.find(id)->protocol.points().size(), 5u);
  EXPECT_EQ(svc.check_pairing(id, code).status, PairingStatus::Outdated);
  EXPECT_EQ(svc.check_pairing(id, "000000").status, PairingStatus::Outdated);
  EXPECT_EQ(SessionStore(db).pairing(id)->failures, 0);
  const auto fresh = svc.reissue_pairing(id);
  ASSERT_TRUE(fresh);
  EXPECT_TRUE(svc.check_pairing(id, *fresh).paired());
  EXPECT_EQ(SessionStore(db).pairing(id)->verifier.rfind("pbkdf2-sha256$", 0), 0u);
  // Damaged verifiers (tiny or huge iteration counts, bad hex) are refused the same way.
  for (const std::string& bad : std::vector<std::string>{"pbkdf2-sha256$1$" + salt + salt + "$" + std::string(64, 'a'),
                                "pbkdf2-sha256$2000000000$" + salt + salt + "$" + std::string(64, 'a'),
                                "pbkdf2-sha256$200000$zz$" + std::string(64, 'a'), std::string("")}) {
    sqlite3* h = nullptr;
    ASSERT_EQ(sqlite3_open(db.c_str(), &h), SQLITE_OK);
    exec_sql(h, "UPDATE sessions SET pairing_hash = '" + bad + "'");
    sqlite3_close(h);
    EXPECT_EQ(svc.check_pairing(id, *fresh).status, PairingStatus::Outdated) << bad;
  }
}

// The live-session cache holds at most max_cached_sessions; sessions dropped from it come back
// from the store with their points; listing every session does not fill it.
TEST(CaptureServiceCache, SessionsBeyondTheBoundAreDroppedAndReloadedFromTheStore) {
  TempDir dir;
  CaptureServiceOptions o = service_options(dir / "sessions.db");
  o.max_cached_sessions = 4;
  CaptureService svc(o);
  test::ScriptedPerson person;
  std::vector<std::string> ids;
  for (int i = 0; i < 12; ++i) {
    ids.push_back(svc.create({}).session.id);
    EXPECT_LE(svc.cached_session_count(), 4u);
  }
  test::SampleScript s(ProfileRegistry::builtin().find("meta-quest-touch-plus")->tip_offset, 9);
  test::script_floor(s, person);
  for (const auto& b : s.batches()) ASSERT_TRUE(svc.feed(ids[0], b, {}));
  const auto before = svc.find(ids[0])->protocol.points();
  ASSERT_EQ(before.size(), 5u);
  for (int i = 1; i < 12; ++i) ASSERT_TRUE(svc.find(ids[i]));  // pushes ids[0] out
  EXPECT_EQ(svc.cached_session_count(), 4u);
  EXPECT_EQ(svc.list().size(), 12u);
  EXPECT_EQ(svc.cached_session_count(), 4u);
  const auto again = svc.find(ids[0]);  // reloaded from the store
  ASSERT_TRUE(again);
  ASSERT_EQ(again->protocol.points().size(), before.size());
  for (size_t i = 0; i < before.size(); ++i) EXPECT_DOUBLE_EQ(again->protocol.points()[i].value_m, before[i].value_m);
  EXPECT_TRUE(again->protocol.floor_m());
  EXPECT_EQ(svc.cached_session_count(), 4u);
}

}  // namespace
}  // namespace caliper::capture
