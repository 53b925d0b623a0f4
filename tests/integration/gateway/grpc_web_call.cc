#include "gateway/grpc_web_call.h"

#include <gtest/gtest.h>

namespace armature::testing {
namespace {

// The test's own base64 (RFC 4648), independent of the server's.
const std::string kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string PercentDecoded(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '%' && i + 2 < s.size()) {
      out += static_cast<char>(std::stoi(s.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

}  // namespace

std::string ToBase64(const std::string& in) {
  std::string out;
  int bits = 0, value = 0;
  for (unsigned char c : in) {
    value = (value << 8) | c;
    bits += 8;
    while (bits >= 6) out += kAlphabet[(value >> (bits -= 6)) & 63];
  }
  if (bits > 0) out += kAlphabet[(value << (6 - bits)) & 63];
  while (out.size() % 4) out += '=';
  return out;
}

std::string FromBase64(const std::string& in) {
  std::string out;
  for (size_t group = 0; group + 4 <= in.size(); group += 4) {  // padded chunks may be concatenated
    int bits = 0, value = 0;
    for (size_t i = group; i < group + 4 && in[i] != '='; ++i) {
      value = (value << 6) | static_cast<int>(kAlphabet.find(in[i]));
      bits += 6;
      if (bits >= 8) out += static_cast<char>((value >> (bits -= 8)) & 0xff);
    }
  }
  return out;
}

std::string Frame(const std::string& message, uint8_t flag) {
  const auto n = static_cast<uint32_t>(message.size());
  std::string out{static_cast<char>(flag), static_cast<char>(n >> 24), static_cast<char>(n >> 16),
                  static_cast<char>(n >> 8), static_cast<char>(n)};
  return out + message;
}

GrpcWebAnswer Call(httplib::Client& http, const std::string& path, const std::string& body, bool text,
                   httplib::Headers headers, const std::string& content_type) {
  headers.emplace("X-Grpc-Web", "1");
  const std::string type = !content_type.empty() ? content_type
                           : text                ? "application/grpc-web-text"
                                                 : "application/grpc-web+proto";
  const auto r = http.Post(path, headers, text ? ToBase64(body) : body, type);
  GrpcWebAnswer a;
  if (!r) return a;
  a.http_status = r->status;
  a.content_type = r->get_header_value("Content-Type");
  const std::string bytes = text ? FromBase64(r->body) : r->body;
  size_t at = 0;
  while (at + 5 <= bytes.size()) {
    const auto flag = static_cast<uint8_t>(bytes[at]);
    const uint32_t n = (static_cast<uint8_t>(bytes[at + 1]) << 24) | (static_cast<uint8_t>(bytes[at + 2]) << 16) |
                       (static_cast<uint8_t>(bytes[at + 3]) << 8) | static_cast<uint8_t>(bytes[at + 4]);
    const std::string payload = bytes.substr(at + 5, n);
    at += 5 + n;
    if (flag == 0x80) {
      ++a.trailer_frames;
      size_t line = 0;
      while (line < payload.size()) {
        const size_t end = payload.find("\r\n", line);
        const std::string header = payload.substr(line, end - line);
        const size_t colon = header.find(':');
        std::string value = header.substr(colon + 1);
        value.erase(0, value.find_first_not_of(' '));
        a.trailers[header.substr(0, colon)] = PercentDecoded(value);
        line = end == std::string::npos ? payload.size() : end + 2;
      }
    } else {
      EXPECT_EQ(a.trailer_frames, 0) << "a data frame after the trailers";
      a.messages.push_back(payload);
    }
  }
  EXPECT_EQ(at, bytes.size()) << "a frame cut short";
  return a;
}

httplib::Client Http(const ServerProcess& server) {
  httplib::Client http("127.0.0.1", server.http_port());
  http.set_read_timeout(60);
  return http;
}

}  // namespace armature::testing
