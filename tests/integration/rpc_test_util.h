// What the integration tests share on the client side: options for a test
// server, and the status code or message a call fails with.
#pragma once

#include <chrono>
#include <functional>
#include <string>

#include "armature/client.h"
#include "server_process.h"

namespace armature::testing {

inline ClientOptions OptionsFor(const ServerProcess& server) {
  ClientOptions o;
  o.target = server.target();
  o.timeout = std::chrono::seconds(30);
  return o;
}

// OK when `call` does not throw.
inline grpc::StatusCode CodeOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const ClientError& e) {
    return e.code();
  }
  return grpc::StatusCode::OK;
}

// "" when `call` does not throw.
inline std::string MessageOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const ClientError& e) {
    return e.what();
  }
  return "";
}

}  // namespace armature::testing
