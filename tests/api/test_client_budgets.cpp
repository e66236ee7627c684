// Budgets that hold against a client changing its address (docs/api.md "Pairing"): IPv6 clients
// are counted by /64 (client_group), the event windows forget and stay bounded (RecentEvents), and
// sessions created by devices other than the desktop are limited per device and in all, while
// the desktop is never refused.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "capture_api.h"
#include "client_group.h"
#include "recent_events.h"
#include "temp_files.h"

namespace caliper::server {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

TEST(ClientGroup, Ipv4IsItselfAndIpv6IsItsSlash64) {
  EXPECT_EQ(client_group("192.0.2.7"), "192.0.2.7");
  EXPECT_EQ(client_group("::ffff:192.0.2.7"), "192.0.2.7") << "a v4-mapped address is the IPv4 client";
  EXPECT_EQ(client_group("2001:db8:1:2:a:b:c:d"), "2001:db8:1:2::/64");
  EXPECT_EQ(client_group("2001:db8:1:2::99"), client_group("2001:0db8:0001:0002:ffff:0:0:1"))
      << "any two addresses in one /64, however written, are one client";
  EXPECT_NE(client_group("2001:db8:1:2::1"), client_group("2001:db8:1:3::1"));
  EXPECT_EQ(client_group("::1"), "0:0:0:0::/64");
  EXPECT_EQ(client_group(""), "");
  EXPECT_EQ(client_group("not an address"), "not an address");
}

TEST(RecentEvents, FullWithinTheWindowAndForgetsAfterIt) {
  RecentEvents e(3, 60s, 100);
  const auto t0 = RecentEvents::Clock::time_point{} + 1000s;
  for (int i = 0; i < 3; ++i) {
    EXPECT_FALSE(e.full("a", t0 + std::chrono::seconds(i)));
    e.record("a", t0 + std::chrono::seconds(i));
  }
  EXPECT_TRUE(e.full("a", t0 + 10s));
  EXPECT_FALSE(e.full("b", t0 + 10s)) << "keys are counted apart";
  EXPECT_FALSE(e.full("a", t0 + 61s)) << "the first event left the window";
  EXPECT_TRUE(e.try_record("a", t0 + 61s));
  EXPECT_FALSE(e.try_record("a", t0 + 61s));
}

TEST(RecentEvents, AFloodOfNewKeysKeepsItBoundedDroppingExpiredKeysFirst) {
  RecentEvents e(2, 60s, 4);
  const auto t0 = RecentEvents::Clock::time_point{} + 1000s;
  e.record("old", t0);
  e.record("zz-live", t0 + 90s);
  e.record("zz-live", t0 + 90s);
  for (int i = 0; i < 2; ++i) e.record(std::string(1, static_cast<char>('a' + i)), t0 + 100s);
  EXPECT_EQ(e.keys(), 4u);
  e.record("c", t0 + 100s);  // full: "old" has expired and goes, not "a" (first in order)
  EXPECT_EQ(e.keys(), 4u);
  EXPECT_TRUE(e.full("zz-live", t0 + 100s));
  for (int i = 0; i < 1000; ++i) {
    std::string key = "flood-";
    key += std::to_string(i);
    e.record(key, t0 + 100s);
  }
  EXPECT_EQ(e.keys(), 4u) << "a flood of new keys does not grow the table";
}

ApiResponse create_from(const CaptureApi& api, const std::string& address) {
  ApiRequest r;
  r.method = "POST";
  r.path = "/api/sessions";
  r.remote_address = address;
  r.local_address = "192.168.1.10";
  r.body = "{}";
  r.content_type = "application/json";
  return api.handle(r);
}

void expect_refused(const ApiResponse& r, const std::string& why) {
  EXPECT_EQ(r.status, 429) << why << ": " << r.body;
  const json j = json::parse(r.body);
  EXPECT_EQ(j["error"]["field"], "session") << r.body;
  EXPECT_EQ(j["error"]["kind"], "too_many_sessions") << r.body;
  EXPECT_NE(j["error"]["message"].get<std::string>().find("desktop"), std::string::npos)
      << "the refusal says where sessions can still be created: " << r.body;
}

TEST(SessionCreationBudget, PerDeviceInAllAndNeverTheDesktop) {
  test::TempDir dir;
  CaptureApiOptions o{dir / "s.db", {}, false, {}, {}, {}};
  o.creation.per_device = 2;
  o.creation.by_devices = 5;
  const CaptureApi api(o);
  // One device: 2, then refused; its IPv6 neighbours in the same /64 share its budget.
  EXPECT_EQ(create_from(api, "2001:db8:1:2::10").status, 201);
  EXPECT_EQ(create_from(api, "2001:db8:1:2::11").status, 201);
  expect_refused(create_from(api, "2001:db8:1:2::12"), "a third session from the same /64");
  // A malformed request is refused for itself and spends nothing.
  ApiRequest bad;
  bad.method = "POST", bad.path = "/api/sessions", bad.remote_address = "192.0.2.50", bad.body = "{\"mode\": 3}";
  EXPECT_EQ(api.handle(bad).status, 400);
  // Rotating addresses: every new address may create, until devices together reach 5.
  EXPECT_EQ(create_from(api, "192.0.2.50").status, 201);
  EXPECT_EQ(create_from(api, "192.0.2.51").status, 201);
  EXPECT_EQ(create_from(api, "192.0.2.52").status, 201);
  expect_refused(create_from(api, "192.0.2.53"), "the sixth session from devices, from a fresh address");
  // The desktop (loopback, or the server's own address) is never refused.
  for (int i = 0; i < 3; ++i) EXPECT_EQ(create_from(api, "127.0.0.1").status, 201);
  EXPECT_EQ(create_from(api, "192.168.1.10").status, 201);
}

}  // namespace
}  // namespace caliper::server
