// Which clients share a budget (connection cap, wrong pairing codes, sessions created). An IPv4
// address is one client. An IPv6 host is normally given a whole /64 and can pick any address in
// it (privacy addresses change by design), so per-address limits would be escaped by counting
// through the prefix: IPv6 clients are grouped by their /64.
#pragma once
#include <string>

namespace caliper::server {

// "192.0.2.7" → "192.0.2.7"; "::ffff:192.0.2.7" → "192.0.2.7"; "2001:db8:1:2:a:b:c:d" →
// "2001:db8:1:2::/64". Anything that is not a numeric address is returned unchanged.
std::string client_group(const std::string& address);

}  // namespace caliper::server
