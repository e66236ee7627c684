// PBKDF2-HMAC-SHA256 pairing verifiers (RFC 8018 §5.2) through OpenSSL's libcrypto.
#include "pairing_verifier.h"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/rand.h>

#include <charconv>
#include <vector>

#include "caliper/errors.h"

namespace caliper::capture::detail {

namespace {

constexpr const char* kScheme = "pbkdf2-sha256";
constexpr int kSaltBytes = 16;
constexpr int kKeyBytes = 32;

std::string to_hex(const unsigned char* bytes, size_t n) {
  static const char* digits = "0123456789abcdef";
  std::string s(n * 2, '0');
  for (size_t i = 0; i < n; ++i) {
    s[2 * i] = digits[bytes[i] >> 4];
    s[2 * i + 1] = digits[bytes[i] & 15];
  }
  return s;
}

bool from_hex(const std::string& hex, std::vector<unsigned char>& out) {
  if (hex.size() % 2) return false;
  out.assign(hex.size() / 2, 0);
  for (size_t i = 0; i < hex.size(); ++i) {
    const char c = hex[i];
    int v;
    if (c >= '0' && c <= '9') v = c - '0';
    else if (c >= 'a' && c <= 'f') v = c - 'a' + 10;
    else return false;
    out[i / 2] = static_cast<unsigned char>(out[i / 2] << 4 | v);
  }
  return true;
}

std::vector<unsigned char> random_bytes(int n) {
  std::vector<unsigned char> b(static_cast<size_t>(n));
  if (RAND_bytes(b.data(), n) != 1) throw Error(ErrorKind::Io, "the system's random number generator failed", "pairing_code");
  return b;
}

std::vector<unsigned char> derive(const std::string& code, const std::vector<unsigned char>& salt, int iterations) {
  std::vector<unsigned char> key(kKeyBytes);
  if (PKCS5_PBKDF2_HMAC(code.data(), static_cast<int>(code.size()), salt.data(), static_cast<int>(salt.size()), iterations,
                        EVP_sha256(), kKeyBytes, key.data()) != 1)
    throw Error(ErrorKind::Io, "PBKDF2 failed (OpenSSL)", "pairing_code");
  return key;
}

}  // namespace

std::string random_hex_bytes(int n) {
  const auto b = random_bytes(n);
  return to_hex(b.data(), b.size());
}

std::string random_decimal_digits(int n) {
  std::string s;
  while (static_cast<int>(s.size()) < n)
    for (unsigned char byte : random_bytes(n))
      if (byte < 250 && static_cast<int>(s.size()) < n) s += static_cast<char>('0' + byte % 10);  // 250 = 25·10: unbiased
  return s;
}

std::string make_pairing_verifier(const std::string& code, int iterations) {
  const std::vector<unsigned char> salt = random_bytes(kSaltBytes);
  const std::vector<unsigned char> key = derive(code, salt, iterations);
  return std::string(kScheme) + "$" + std::to_string(iterations) + "$" + to_hex(salt.data(), salt.size()) + "$" +
         to_hex(key.data(), key.size());
}

VerifierMatch match_pairing_verifier(const std::string& verifier, const std::string& code) {
  // scheme $ iterations $ salt $ key
  std::vector<std::string> parts;
  size_t start = 0;
  for (;;) {
    const size_t dollar = verifier.find('$', start);
    parts.push_back(verifier.substr(start, dollar == std::string::npos ? std::string::npos : dollar - start));
    if (dollar == std::string::npos) break;
    start = dollar + 1;
  }
  if (parts.size() != 4 || parts[0] != kScheme) return VerifierMatch::Unsupported;
  int iterations = 0;
  const auto [end, ec] = std::from_chars(parts[1].data(), parts[1].data() + parts[1].size(), iterations);
  if (ec != std::errc() || end != parts[1].data() + parts[1].size() || iterations < kMinPairingIterations ||
      iterations > kMaxPairingIterations)
    return VerifierMatch::Unsupported;
  std::vector<unsigned char> salt, key;
  if (!from_hex(parts[2], salt) || salt.size() != kSaltBytes || !from_hex(parts[3], key) || key.size() != kKeyBytes)
    return VerifierMatch::Unsupported;
  const std::vector<unsigned char> got = derive(code, salt, iterations);
  return CRYPTO_memcmp(got.data(), key.data(), kKeyBytes) == 0 ? VerifierMatch::Match : VerifierMatch::Mismatch;
}

}  // namespace caliper::capture::detail
