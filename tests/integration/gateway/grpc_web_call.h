// gRPC-Web calls framed by hand from the protocol text (flag byte, 4-byte
// big-endian length; trailers as header lines) over httplib::Client, with the
// test's own base64, independent of the server's: the gateway tests' client.
#pragma once

#include <httplib.h>

#include <map>
#include <string>
#include <vector>

#include "support/server_process.h"

namespace armature::testing {

std::string ToBase64(const std::string& in);
std::string FromBase64(const std::string& in);
// A message as a gRPC-Web frame (flag 0: data, 0x80: trailers).
std::string Frame(const std::string& message, uint8_t flag = 0);

struct GrpcWebAnswer {
  int http_status = 0;
  std::string content_type;
  std::vector<std::string> messages;
  std::map<std::string, std::string> trailers;  // grpc-message percent-decoded
  int trailer_frames = 0;
  int code() const { return trailers.count("grpc-status") ? std::stoi(trailers.at("grpc-status")) : -1; }
  std::string message() const { return trailers.count("grpc-message") ? trailers.at("grpc-message") : ""; }
};

// POSTs `body` (framed requests) to `path`; binary or text (base64) mode.
GrpcWebAnswer Call(httplib::Client& http, const std::string& path, const std::string& body, bool text = false,
                   httplib::Headers headers = {}, const std::string& content_type = "");

// An HTTP client on the server's HTTP port, reading for up to 60 s.
httplib::Client Http(const ServerProcess& server);

}  // namespace armature::testing
