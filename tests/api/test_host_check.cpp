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

TEST(OriginCheck, OwnPagesAndNonBrowsersMayWrite) {
  EXPECT_TRUE(origin_is_same_host("", "127.0.0.1:8080"));  // curl, the CLI, scripts
  EXPECT_TRUE(origin_is_same_host("http://127.0.0.1:8080", "127.0.0.1:8080"));
  EXPECT_TRUE(origin_is_same_host("https://192.168.1.20:8443", "192.168.1.20:8443"));
  EXPECT_TRUE(origin_is_same_host("http://[::1]:8080", "[::1]:8080"));
  EXPECT_TRUE(origin_is_same_host("http://LocalHost", "localhost:80"));      // default port, case
  EXPECT_TRUE(origin_is_same_host("https://studio-pc.local:443", "Studio-PC.local"));
}

TEST(OriginCheck, OtherSitesAndOpaqueOriginsMayNot) {
  for (const char* origin : {"http://evil.example", "http://evil.example:8080", "null", "file://", "ftp://127.0.0.1:8080",
                             "http://127.0.0.1:8081", "http://127.0.0.1:8080/path", "127.0.0.1:8080", "http://"})
    EXPECT_FALSE(origin_is_same_host(origin, "127.0.0.1:8080")) << origin;
  EXPECT_FALSE(origin_is_same_host("http://127.0.0.1", "127.0.0.1:443"));  // :443 is not http's default
  EXPECT_FALSE(origin_is_same_host("http://127.0.0.1:8080", ""));
}

}  // namespace
}  // namespace caliper::server
