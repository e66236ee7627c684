// Self-signed certificate generation with OpenSSL 3 (EVP + X509), and the LAN addresses to print.
#include "tls_certificate.h"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>

#include <cstdio>
#include <filesystem>
#include <memory>

#include "caliper/errors.h"
#include "caliper/private_files.h"

namespace caliper::server {

namespace {

[[noreturn]] void fail(const std::string& what) { throw Error(ErrorKind::Io, "cannot make a TLS certificate: " + what, "--https"); }

// The private key as PEM text (PKCS#8, unencrypted), written to memory rather than to a file.
std::string key_pem(EVP_PKEY* key) {
  std::unique_ptr<BIO, decltype(&BIO_free)> bio(BIO_new(BIO_s_mem()), BIO_free);
  if (!bio || PEM_write_bio_PrivateKey(bio.get(), key, nullptr, nullptr, 0, nullptr, nullptr) != 1)
    fail("writing the private key failed");
  char* data = nullptr;
  const long size = BIO_get_mem_data(bio.get(), &data);
  return std::string(data, static_cast<std::size_t>(size));
}

bool is_ip(const std::string& h) {
  unsigned char buf[16];
  return inet_pton(AF_INET, h.c_str(), buf) == 1 || inet_pton(AF_INET6, h.c_str(), buf) == 1;
}

}  // namespace

CertificateFiles ensure_self_signed_certificate(const std::string& dir, const std::vector<std::string>& hosts) {
  namespace fs = std::filesystem;
  CertificateFiles out;
  out.cert_file = (fs::path(dir) / "caliper-cert.pem").string();
  out.key_file = (fs::path(dir) / "caliper-key.pem").string();
  std::error_code ec;
  if (fs::exists(out.cert_file, ec) && fs::exists(out.key_file, ec)) {
    restrict_to_owner(out.key_file);  // a key left readable by an older Caliper or by hand
    return out;
  }
  create_private_directory(dir);

  std::unique_ptr<EVP_PKEY, decltype(&EVP_PKEY_free)> key(EVP_EC_gen("P-256"), EVP_PKEY_free);
  if (!key) fail("key generation failed");
  std::unique_ptr<X509, decltype(&X509_free)> cert(X509_new(), X509_free);
  if (!cert) fail("out of memory");
  X509_set_version(cert.get(), 2);
  unsigned char serial[16];
  FILE* urandom = std::fopen("/dev/urandom", "rb");
  if (!urandom || std::fread(serial, 1, sizeof serial, urandom) != sizeof serial) {
    if (urandom) std::fclose(urandom);
    fail("no /dev/urandom");
  }
  std::fclose(urandom);
  serial[0] &= 0x7f;  // a positive serial number
  BIGNUM* bn = BN_bin2bn(serial, sizeof serial, nullptr);
  BN_to_ASN1_INTEGER(bn, X509_get_serialNumber(cert.get()));
  BN_free(bn);
  X509_gmtime_adj(X509_getm_notBefore(cert.get()), -3600);
  X509_gmtime_adj(X509_getm_notAfter(cert.get()), 60L * 60 * 24 * 730);
  X509_set_pubkey(cert.get(), key.get());
  X509_NAME* name = X509_get_subject_name(cert.get());
  X509_NAME_add_entry_by_txt(name, "O", MBSTRING_ASC, reinterpret_cast<const unsigned char*>("Caliper"), -1, -1, 0);
  X509_NAME_add_entry_by_txt(name, "CN", MBSTRING_ASC, reinterpret_cast<const unsigned char*>("Caliper capture server"), -1, -1, 0);
  X509_set_issuer_name(cert.get(), name);
  std::string san;
  for (const auto& h : hosts) {
    if (h.empty()) continue;
    if (!san.empty()) san += ',';
    san.append(is_ip(h) ? "IP:" : "DNS:").append(h);  // piecewise: GCC 12 warns falsely on operator+ chains
  }
  if (!san.empty()) {
    X509V3_CTX ctx;
    X509V3_set_ctx_nodb(&ctx);
    X509V3_set_ctx(&ctx, cert.get(), cert.get(), nullptr, nullptr, 0);
    X509_EXTENSION* ext = X509V3_EXT_conf_nid(nullptr, &ctx, NID_subject_alt_name, san.c_str());
    if (!ext) fail("bad subjectAltName '" + san + "'");
    X509_add_ext(cert.get(), ext, -1);
    X509_EXTENSION_free(ext);
  }
  if (X509_sign(cert.get(), key.get(), EVP_sha256()) == 0) fail("signing failed");

  // The key is readable by its owner only (0600 also when an old key file is rewritten).
  write_private_file(out.key_file, key_pem(key.get()));
  FILE* cf = std::fopen(out.cert_file.c_str(), "wb");
  if (!cf) fail("cannot write " + out.cert_file);
  const bool cert_ok = PEM_write_X509(cf, cert.get()) == 1;
  std::fclose(cf);
  if (!cert_ok) fail("writing the PEM files failed");
  out.created = true;
  return out;
}

std::vector<std::string> lan_addresses() {
  std::vector<std::string> out;
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) return out;
  for (ifaddrs* a = list; a; a = a->ifa_next) {
    if (!a->ifa_addr || a->ifa_addr->sa_family != AF_INET) continue;
    char buf[INET_ADDRSTRLEN];
    const auto* in = reinterpret_cast<const sockaddr_in*>(a->ifa_addr);
    if (!inet_ntop(AF_INET, &in->sin_addr, buf, sizeof buf)) continue;
    const std::string ip = buf;
    if (ip.rfind("127.", 0) == 0) continue;
    out.push_back(ip);
  }
  freeifaddrs(list);
  return out;
}

}  // namespace caliper::server
