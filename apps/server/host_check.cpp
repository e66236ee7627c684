#include "host_check.h"

#include <algorithm>
#include <cctype>

namespace caliper::server {
namespace {

bool all_digits(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c) != 0; });
}

// Lower case, without a trailing dot ("Example.COM." names the same host as "example.com").
std::string normalised(std::string name) {
  for (auto& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (!name.empty() && name.back() == '.') name.pop_back();
  return name;
}

bool is_ipv4(const std::string& name) {
  int parts = 0;
  size_t start = 0;
  while (true) {
    const size_t dot = name.find('.', start);
    const std::string part = name.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    if (!all_digits(part) || part.size() > 3 || std::stoi(part) > 255) return false;
    ++parts;
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return parts == 4;
}

}  // namespace

bool host_is_allowed(const std::string& host_header, const std::vector<std::string>& extra_names) {
  std::string host = host_header;
  host.erase(0, host.find_first_not_of(" \t"));
  host.erase(host.find_last_not_of(" \t") + 1);
  if (host.empty()) return true;
  if (host.front() == '[') {  // [IPv6]:port
    const size_t close = host.find(']');
    if (close == std::string::npos || close == 1) return false;
    const std::string address = host.substr(1, close - 1), rest = host.substr(close + 1);
    const bool ipv6 = std::all_of(address.begin(), address.end(),
                                  [](unsigned char c) { return std::isxdigit(c) != 0 || c == ':' || c == '.'; });
    return ipv6 && address.find(':') != std::string::npos && (rest.empty() || (rest[0] == ':' && all_digits(rest.substr(1))));
  }
  if (const size_t colon = host.rfind(':'); colon != std::string::npos) {
    if (!all_digits(host.substr(colon + 1))) return false;
    host.erase(colon);
  }
  host = normalised(host);
  if (host.empty()) return false;
  if (is_ipv4(host) || host == "localhost" || (host.size() > 10 && host.ends_with(".localhost"))) return true;
  return std::any_of(extra_names.begin(), extra_names.end(), [&](const std::string& n) { return normalised(n) == host; });
}

bool origin_is_same_host(const std::string& origin_header, const std::string& host_header) {
  if (origin_header.empty()) return true;
  const std::string origin = normalised(origin_header);
  const size_t scheme_end = origin.find("://");
  if (scheme_end == std::string::npos) return false;  // includes "null"
  const std::string scheme = origin.substr(0, scheme_end);
  if (scheme != "http" && scheme != "https") return false;
  std::string origin_host = origin.substr(scheme_end + 3), host = normalised(host_header);
  if (origin_host.empty() || origin_host.find('/') != std::string::npos || host.empty()) return false;
  const std::string default_port = scheme == "http" ? ":80" : ":443";
  for (std::string* h : {&origin_host, &host})
    if (h->size() > default_port.size() && h->ends_with(default_port)) h->erase(h->size() - default_port.size());
  return origin_host == host;
}

}  // namespace caliper::server
