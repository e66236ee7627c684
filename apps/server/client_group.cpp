#include "client_group.h"

#include <arpa/inet.h>

#include <algorithm>
#include <array>
#include <cstdio>

namespace caliper::server {

std::string client_group(const std::string& address) {
  std::array<unsigned char, 16> a{};
  if (::inet_pton(AF_INET6, address.c_str(), a.data()) != 1) return address;
  const bool v4_mapped = a[10] == 0xff && a[11] == 0xff &&
                         std::all_of(a.begin(), a.begin() + 10, [](unsigned char b) { return b == 0; });
  char text[48];
  if (v4_mapped) {
    std::snprintf(text, sizeof text, "%u.%u.%u.%u", a[12], a[13], a[14], a[15]);
  } else {
    std::snprintf(text, sizeof text, "%x:%x:%x:%x::/64", a[0] << 8 | a[1], a[2] << 8 | a[3], a[4] << 8 | a[5],
                  a[6] << 8 | a[7]);
  }
  return text;
}

}  // namespace caliper::server
