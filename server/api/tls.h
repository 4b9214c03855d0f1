// The server's TLS identity: the configured certificate and key, or a self-signed certificate made on first start and
// kept in <state_dir>/tls (an EC P-256 key, ten years, the host's name and localhost as subject names). Browsers warn
// about a self-signed certificate; the fingerprint printed in the journal and shown on the face screen at setup lets a
// person check that the one their browser shows is the robot's.
#pragma once

#include <filesystem>
#include <string>

#include "server/config/config.h"

namespace corridor::server {

struct TlsIdentity {
  std::filesystem::path certificate;  // PEM
  std::filesystem::path key;          // PEM
  std::string fingerprint;            // SHA-256 of the certificate (DER), "AB:CD:..."
  bool generated = false;             // made now, on this start
};

// The configured certificate, or the generated one (made when missing). Throws std::runtime_error naming the file
// when a configured one cannot be read or a new one cannot be written.
TlsIdentity LoadOrCreateTlsIdentity(const TlsOptions& options, const std::filesystem::path& state_dir);

}  // namespace corridor::server
