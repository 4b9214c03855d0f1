#include "server/api/tls.h"

#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/rand.h>
#include <openssl/x509.h>
#include <openssl/x509v3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <stdexcept>

namespace corridor::server {
namespace {

namespace fs = std::filesystem;

template <typename T, void (*Free)(T*)>
struct Deleter {
  void operator()(T* p) const { Free(p); }
};
void CloseFile(FILE* f) { std::fclose(f); }
using Key = std::unique_ptr<EVP_PKEY, Deleter<EVP_PKEY, EVP_PKEY_free>>;
using Certificate = std::unique_ptr<X509, Deleter<X509, X509_free>>;
using File = std::unique_ptr<FILE, Deleter<FILE, CloseFile>>;

std::string HostName() {
  char name[256] = {};
  if (gethostname(name, sizeof(name) - 1) != 0 || name[0] == '\0') return "corridor";
  return name;
}

Certificate ReadCertificate(const fs::path& file) {
  File in(std::fopen(file.c_str(), "r"));
  if (!in) throw std::runtime_error("server.tls.certificate: cannot read " + file.string());
  Certificate cert(PEM_read_X509(in.get(), nullptr, nullptr, nullptr));
  if (!cert) throw std::runtime_error("server.tls.certificate: " + file.string() + " is not a PEM certificate");
  return cert;
}

std::string Fingerprint(X509* cert) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  X509_digest(cert, EVP_sha256(), digest, &length);
  std::string out;
  char hex[4];
  for (unsigned int i = 0; i < length; ++i) {
    std::snprintf(hex, sizeof(hex), i == 0 ? "%02X" : ":%02X", digest[i]);
    out += hex;
  }
  return out;
}

void AddExtension(X509* cert, int nid, const std::string& value) {
  X509V3_CTX ctx;
  X509V3_set_ctx_nodb(&ctx);
  X509V3_set_ctx(&ctx, cert, cert, nullptr, nullptr, 0);
  X509_EXTENSION* ext = X509V3_EXT_conf_nid(nullptr, &ctx, nid, value.c_str());
  if (ext == nullptr) throw std::runtime_error("TLS: cannot make the certificate's extension " + value);
  X509_add_ext(cert, ext, -1);
  X509_EXTENSION_free(ext);
}

// A self-signed certificate for this host, written to `cert_file` and `key_file` (the key readable by its owner only).
void MakeSelfSigned(const fs::path& cert_file, const fs::path& key_file) {
  Key key(EVP_EC_gen("P-256"));
  if (!key) throw std::runtime_error("TLS: cannot make a key");
  Certificate cert(X509_new());
  X509_set_version(cert.get(), 2);
  unsigned char serial[16];
  RAND_bytes(serial, sizeof(serial));
  serial[0] &= 0x7f;  // positive
  BIGNUM* bn = BN_bin2bn(serial, sizeof(serial), nullptr);
  BN_to_ASN1_INTEGER(bn, X509_get_serialNumber(cert.get()));
  BN_free(bn);
  X509_gmtime_adj(X509_getm_notBefore(cert.get()), -60);
  X509_gmtime_adj(X509_getm_notAfter(cert.get()), 10L * 365 * 24 * 3600);
  X509_set_pubkey(cert.get(), key.get());
  const std::string host = HostName();
  X509_NAME* name = X509_get_subject_name(cert.get());
  X509_NAME_add_entry_by_txt(name, "O", MBSTRING_ASC, reinterpret_cast<const unsigned char*>("corridor robot"), -1, -1,
                             0);
  X509_NAME_add_entry_by_txt(name, "CN", MBSTRING_ASC, reinterpret_cast<const unsigned char*>(host.c_str()), -1, -1, 0);
  X509_set_issuer_name(cert.get(), name);
  AddExtension(cert.get(), NID_subject_alt_name,
               "DNS:" + host + ",DNS:" + host + ".local,DNS:localhost,IP:127.0.0.1,IP:::1");
  AddExtension(cert.get(), NID_basic_constraints, "critical,CA:FALSE");
  AddExtension(cert.get(), NID_key_usage, "critical,digitalSignature");
  AddExtension(cert.get(), NID_ext_key_usage, "serverAuth");
  if (X509_sign(cert.get(), key.get(), EVP_sha256()) == 0) throw std::runtime_error("TLS: cannot sign the certificate");

  const mode_t old_mask = umask(077);
  File key_out(std::fopen(key_file.c_str(), "w"));
  umask(old_mask);
  if (!key_out || !PEM_write_PrivateKey(key_out.get(), key.get(), nullptr, nullptr, 0, nullptr, nullptr)) {
    throw std::runtime_error("TLS: cannot write " + key_file.string());
  }
  File cert_out(std::fopen(cert_file.c_str(), "w"));
  if (!cert_out || !PEM_write_X509(cert_out.get(), cert.get())) {
    throw std::runtime_error("TLS: cannot write " + cert_file.string());
  }
}

}  // namespace

TlsIdentity LoadOrCreateTlsIdentity(const TlsOptions& options, const fs::path& state_dir) {
  TlsIdentity id{options.certificate, options.key, "", false};
  if (id.certificate.empty()) {
    const fs::path dir = state_dir / "tls";
    std::error_code ec;
    fs::create_directories(dir, ec);
    id.certificate = dir / "certificate.pem";
    id.key = dir / "key.pem";
    if (!fs::exists(id.certificate) || !fs::exists(id.key)) {
      MakeSelfSigned(id.certificate, id.key);
      id.generated = true;
    }
  }
  if (!fs::exists(id.key)) throw std::runtime_error("server.tls.key: cannot read " + id.key.string());
  id.fingerprint = Fingerprint(ReadCertificate(id.certificate).get());
  return id;
}

}  // namespace corridor::server
