// Pairing-code verifiers, internal to the capture stage. A 6-digit code has only 10^6 values, so
// a fast hash of it is no protection for anyone who can read sessions.db: the verifier is
// PBKDF2-HMAC-SHA256 (RFC 8018 §5.2) with a per-session random salt and enough iterations that
// trying every code offline takes hours (docs/reliability.md "Pairing codes" has the figures).
// OpenSSL's libcrypto computes it; openssl headers stay in pairing_verifier.cpp.
#pragma once
#include <string>

namespace caliper::capture::detail {

// Iterations for new verifiers. Stored in each verifier, so it can be raised later without
// invalidating existing sessions.
constexpr int kPairingIterations = 200000;
// Stored iteration counts outside [kMinPairingIterations, kMaxPairingIterations] are refused as
// damaged (a tiny count would make the code cheap to recover, a huge one would stall the server).
constexpr int kMinPairingIterations = 10000;
constexpr int kMaxPairingIterations = 10000000;

// "pbkdf2-sha256$<iterations>$<salt: 32 hex = 16 random bytes>$<derived key: 64 hex = 32 bytes>".
std::string make_pairing_verifier(const std::string& code, int iterations = kPairingIterations);

enum class VerifierMatch { Match, Mismatch, Unsupported };
// Recomputes the key from `code` and the verifier's salt and iterations; compares in constant
// time. Unsupported: not a verifier in the format above (e.g. the salted SHA-256 of Caliper
// before schema 2, "<16 hex>$<64 hex>"), or its iteration count is out of range.
VerifierMatch match_pairing_verifier(const std::string& verifier, const std::string& code);

// n bytes from OpenSSL's CSPRNG as 2n lower-case hex digits; throws Error(Io) if it fails.
std::string random_hex_bytes(int n);
// n random decimal digits (uniform; rejection sampling over CSPRNG bytes).
std::string random_decimal_digits(int n);

}  // namespace caliper::capture::detail
