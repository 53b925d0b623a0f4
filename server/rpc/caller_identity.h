// Who a call comes from, read from its metadata: the bearer token for the
// auth gate, and the client identity that per-client limits count by.
#pragma once

#include <string>

#include <grpcpp/grpcpp.h>

namespace armature::server {

// The `authorization` metadata of a call ("" when absent).
std::string AuthorizationOf(const grpc::ServerContextBase& context);

// Metadata the REST gateway sets on its in-process calls: the HTTP client's address.
inline constexpr char kRestPeerMetadata[] = "x-armature-rest-peer";

// The client a call comes from, for per-client limits: "token:<authorization>"
// when it sends a bearer token, "rest:<address>" for a REST client, else
// "peer:<address without the port>".
std::string ClientIdentityOf(const grpc::ServerContextBase& context);

}  // namespace armature::server
