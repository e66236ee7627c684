// A self-signed TLS certificate for `caliper serve --https`, made once into the data folder so
// a headset on the LAN gets a secure context (WebXR needs one). OpenSSL stays in the .cpp.
#pragma once
#include <string>
#include <vector>

namespace caliper::server {

struct CertificateFiles {
  std::string cert_file, key_file;
  bool created = false;  // false: existing files were reused
};

// Uses `dir`/caliper-cert.pem and `dir`/caliper-key.pem when both exist; otherwise creates an
// EC P-256 key and a certificate valid ~2 years for `hosts` (DNS names or IP addresses, put in
// subjectAltName). The key file has mode 0600 — also when an existing key file is rewritten or
// reused — and a folder this creates 0700. Throws caliper::Error(Io) on failure.
CertificateFiles ensure_self_signed_certificate(const std::string& dir, const std::vector<std::string>& hosts);

// This machine's IPv4 addresses other than loopback (for the URL a headset should open).
std::vector<std::string> lan_addresses();

}  // namespace caliper::server
