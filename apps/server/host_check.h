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

// Cross-site writes: a page on another site can make the visitor's browser POST to this server
// (a text/plain form post needs no preflight), e.g. to create capture sessions. Browsers send
// Origin with every such request; a write is answered only when there is no Origin (curl, the
// CLI, scripts) or it names the host the request was sent to (the server's own pages). "null"
// (sandboxed frames, file: pages) is refused. Default ports (:80 for http, :443 for https) are
// ignored on both sides; letter case too.
bool origin_is_same_host(const std::string& origin_header, const std::string& host_header);

}  // namespace caliper::server
