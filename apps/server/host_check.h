// Which Host headers the server answers. A web page on another site can make the visitor's
// browser send requests to 127.0.0.1 or a LAN address by pointing its own DNS name there (DNS
// rebinding); such requests carry the attacker's name in Host. Answering only names no other
// site can claim keeps capture sessions and the API private (docs/api.md "Host names").
#pragma once
#include <string>
#include <vector>

namespace caliper::server {

// True for an IP address (IPv4 dotted quad or bracketed IPv6), localhost or *.localhost, or one
// of `extra_names`, with or without a port; letter case and a trailing dot are ignored. An
// absent Host is allowed (HTTP/1.0 clients; a browser always sends one).
bool host_is_allowed(const std::string& host_header, const std::vector<std::string>& extra_names);

}  // namespace caliper::server
