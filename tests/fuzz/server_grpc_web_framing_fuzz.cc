// gRPC-Web framing (server/host/gateway/grpc_web/grpc_web_framing): the request body
// parser, base64 and grpc-message's percent-encoding. Input: a byte choosing
// the frame size limit, then a body. Accepted frames re-encode to the body
// byte for byte; a refused body is named by a status; base64 and percent-
// encoding round-trip any bytes, and decoding never grows past its input.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "server/host/gateway/grpc_web/grpc_web_framing.h"

namespace gw = armature::server::gateway;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const size_t limit = size_t{1} << (data[0] % 24);
  const std::string_view body(reinterpret_cast<const char*>(data) + 1, size - 1);

  std::vector<std::string> messages;
  const grpc::Status st = gw::ParseGrpcWebFrames(body, limit, &messages);
  if (st.ok()) {
    std::string again;
    for (const auto& m : messages) {
      if (m.size() > limit) std::abort();
      gw::AppendGrpcWebFrame(gw::kGrpcWebDataFlag, m, &again);
    }
    if (again != body) std::abort();
  } else if (st.error_message().empty() || st.error_message().rfind("gRPC-Web frame ", 0) != 0) {
    std::abort();
  }

  std::string decoded;
  if (gw::Base64Decode(body, &decoded) && decoded.size() > body.size() / 4 * 3) std::abort();
  if (!gw::Base64Decode(gw::Base64Encode(body), &decoded) || decoded != body) std::abort();

  const std::string encoded = gw::PercentEncode(body);
  for (const unsigned char c : encoded)
    if (c < 0x20 || c >= 0x7f) std::abort();
  if (gw::PercentDecode(encoded) != body) std::abort();
  (void)gw::PercentDecode(body);

  // The trailer frame: flag 0x80 and a length prefix that fits its text.
  const std::string trailer =
      gw::GrpcWebTrailerFrame(grpc::Status(static_cast<grpc::StatusCode>(data[0] % 17), std::string(body)));
  const auto* t = reinterpret_cast<const unsigned char*>(trailer.data());
  const size_t length = (size_t{t[1]} << 24) | (size_t{t[2]} << 16) | (size_t{t[3]} << 8) | t[4];
  if (t[0] != 0x80 || length != trailer.size() - 5) std::abort();
  return 0;
}
