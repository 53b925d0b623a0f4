// Bearer-token authentication that rejects a call before its handler runs,
// for every call: over the network and through the in-process channel the
// REST gateway uses.
//
// Why a gate and not the usual hooks: gRPC C++ server interceptors cannot
// fail a call (no Hijack on the server), and an AuthMetadataProcessor needs
// secure credentials (InsecureServerCredentials asserts on it) and never
// sees in-process calls. So a protected service is registered behind a
// GatedService: the same methods, whose handlers check the `authorization`
// metadata and then hand the call either to the real handler or to a
// handler that finishes it with UNAUTHENTICATED without running any
// service code.
#pragma once

#include <memory>
#include <string>

#include <grpcpp/grpcpp.h>

#include "armature/base/status.h"
#include "server/host/auth/bearer_tokens.h"

namespace armature::server {

// Wraps `inner`, a callback service implementing the proto service
// `full_name` (e.g. "armature.v1.AssetService"), so each call needs one of
// `tokens`. INVALID_ARGUMENT if the name is unknown to the generated
// descriptor pool or the service has non-callback methods.
StatusOr<std::unique_ptr<grpc::Service>> GateService(std::unique_ptr<grpc::Service> inner, const std::string& full_name,
                                                     std::shared_ptr<const BearerTokens> tokens);

}  // namespace armature::server
