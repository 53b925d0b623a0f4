// The credentials the gRPC port listens with: TLS from --tls-cert and
// --tls-key, else plaintext.
#pragma once

#include <memory>

#include <grpcpp/security/server_credentials.h>

#include "armature/base/status.h"
#include "server/host/config.h"

namespace armature::server {

// FAILED_PRECONDITION naming the file when the certificate or key cannot be
// read or parsed, or when the key does not belong to the certificate.
StatusOr<std::shared_ptr<grpc::ServerCredentials>> MakeServerCredentials(const ServerConfig& config);

}  // namespace armature::server
