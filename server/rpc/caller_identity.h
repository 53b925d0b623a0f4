// Who a call comes from, read from its metadata: the bearer token for the
// auth gate, and the client identity that per-client limits count by.
#pragma once

#include <string>
#include <string_view>

#include <grpcpp/grpcpp.h>

namespace armature::server {

// The `authorization` metadata of a call ("" when absent).
std::string AuthorizationOf(const grpc::ServerContextBase& context);

// The token of an authorization value "Bearer <token>": the scheme in any
// case, then spaces or tabs, the token without the whitespace around it.
// "" when the value is not of that form.
std::string_view BearerTokenOf(std::string_view authorization);

// Metadata the REST gateway sets on its in-process calls: the HTTP client's address.
inline constexpr char kRestPeerMetadata[] = "x-armature-rest-peer";

// The client a call comes from, for per-client limits. With
// `tokens_verified` (an auth gate let the call in only with an accepted
// token) it is "token:<the token>", however the scheme is spelled; a token
// nobody checked names no one, so otherwise it is the address:
// "rest:<address>" for a REST client, else "peer:<address without the port>".
std::string ClientIdentityOf(const grpc::ServerContextBase& context, bool tokens_verified);

}  // namespace armature::server
