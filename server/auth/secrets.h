// Passwords and secrets (libsodium): Argon2id password hashes in the PHC string format, random secrets for tokens,
// sessions and setup codes, and the digests they are kept as.
#pragma once

#include <string>
#include <string_view>

namespace corridor::server::auth {

// Argon2id with t = 2 passes over m = 19 MiB, one lane (OWASP's minimum); about 40 ms on one core of the robot.
std::string HashPassword(std::string_view password);
// True when `password` matches `hash` (a HashPassword result); false for a wrong password or a malformed hash.
bool VerifyPassword(const std::string& hash, std::string_view password);
// Spends the time of one verification, so that a login for an unknown user takes as long as a wrong password.
void SpendVerificationTime(std::string_view password);

// `bytes` random bytes as URL-safe base64 without padding.
std::string RandomSecret(std::size_t bytes);
// `length` characters from an alphabet without look-alikes (no 0/O, 1/I/L), for codes people type.
std::string RandomCode(std::size_t length);
// A secret's digest as it is stored (BLAKE2b-256, hex): a leaked database does not give the secrets away, and
// secrets have enough entropy that a fast hash is safe.
std::string SecretDigest(std::string_view secret);
// Compares in time independent of where they differ.
bool SameSecret(std::string_view a, std::string_view b);

}  // namespace corridor::server::auth
