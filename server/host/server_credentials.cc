#include "server/host/server_credentials.h"

#include <openssl/evp.h>
#include <openssl/pem.h>
#include <openssl/x509.h>

#include "server/assets/file_io.h"

namespace armature::server {
namespace {

StatusOr<std::string> ReadPem(const std::string& path, const char* what) {
  auto text = ReadFile(path);
  if (!text.ok()) return Status::FailedPrecondition(std::string("cannot read the TLS ") + what + " " + path);
  return text;
}

// Parses both PEMs with OpenSSL first, so a bad file is reported by name
// instead of as a port that cannot be opened.
Status CheckKeyPair(const ServerConfig& config, const std::string& cert_pem, const std::string& key_pem) {
  BIO* cert_bio = BIO_new_mem_buf(cert_pem.data(), static_cast<int>(cert_pem.size()));
  X509* cert = PEM_read_bio_X509(cert_bio, nullptr, nullptr, nullptr);
  BIO_free(cert_bio);
  BIO* key_bio = BIO_new_mem_buf(key_pem.data(), static_cast<int>(key_pem.size()));
  EVP_PKEY* key = PEM_read_bio_PrivateKey(key_bio, nullptr, nullptr, nullptr);
  BIO_free(key_bio);
  Status st;
  if (cert == nullptr)
    st = Status::FailedPrecondition("--tls-cert " + config.tls_cert_file + " is not a PEM certificate");
  else if (key == nullptr)
    st = Status::FailedPrecondition("--tls-key " + config.tls_key_file + " is not a PEM private key");
  else if (X509_check_private_key(cert, key) != 1)
    st = Status::FailedPrecondition("--tls-key " + config.tls_key_file + " does not belong to --tls-cert " +
                                    config.tls_cert_file);
  X509_free(cert);
  EVP_PKEY_free(key);
  return st;
}

}  // namespace

StatusOr<std::shared_ptr<grpc::ServerCredentials>> MakeServerCredentials(const ServerConfig& config) {
  if (config.tls_cert_file.empty()) return grpc::InsecureServerCredentials();
  auto cert = ReadPem(config.tls_cert_file, "certificate");
  if (!cert.ok()) return cert.status();
  auto key = ReadPem(config.tls_key_file, "key");
  if (!key.ok()) return key.status();
  ARMATURE_RETURN_IF_ERROR(CheckKeyPair(config, *cert, *key));
  grpc::SslServerCredentialsOptions options;
  options.pem_key_cert_pairs.push_back({*key, *cert});
  return grpc::SslServerCredentials(options);
}

}  // namespace armature::server
