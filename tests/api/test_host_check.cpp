// Host header check (DNS-rebinding protection): which names the server answers.
#include <gtest/gtest.h>

#include "host_check.h"

namespace caliper::server {
namespace {

TEST(HostCheck, AddressesAndLocalhostAreAnswered) {
  for (const char* host : {"127.0.0.1", "127.0.0.1:8080", "192.168.1.20:8443", "0.0.0.0", "[::1]", "[::1]:8080",
                           "[fe80::1]", "localhost", "LOCALHOST:80", "localhost.", "app.localhost:3000", ""})
    EXPECT_TRUE(host_is_allowed(host, {})) << host;
}

TEST(HostCheck, OtherNamesAreRefusedUnlessAllowed) {
  for (const char* host : {"evil.example", "evil.example:8080", "127.0.0.1.evil.example", "localhost.evil.example",
                           "1.2.3", "1.2.3.4.5", "256.1.1.1", "[evil.example]", "[::1]x", "127.0.0.1:http", "x.localhost.com"})
    EXPECT_FALSE(host_is_allowed(host, {})) << host;
  EXPECT_TRUE(host_is_allowed("Studio-PC.local:8443", {"studio-pc.local"}));
  EXPECT_TRUE(host_is_allowed("studio-pc.local.", {"Studio-PC.local"}));
  EXPECT_FALSE(host_is_allowed("other-pc.local", {"studio-pc.local"}));
}

}  // namespace
}  // namespace caliper::server
