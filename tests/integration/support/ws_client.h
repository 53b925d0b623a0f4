// A WebSocket client for the integration tests, written from RFC 6455 (its
// own framing and masking, the RFC's accept key) over a blocking socket, so
// that the server's WebSocket routes are checked against the RFC rather than
// against a library that shares its reading of it.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace armature::testing {

// RFC 6455 1.3's example key and its accept value.
constexpr char kKey[] = "dGhlIHNhbXBsZSBub25jZQ==";
constexpr char kAccept[] = "s3pPLMBiTxaQ9kYGzzhZRbK+xOo=";

struct Frame {
  int opcode = -1;  // -1: none (timeout or the connection closed)
  std::string payload;
  int close_code() const {
    return payload.size() >= 2 ? (static_cast<uint8_t>(payload[0]) << 8) | static_cast<uint8_t>(payload[1]) : -1;
  }
};

// A WebSocket client over a blocking socket, framing by the RFC's text.
class WsClient {
 public:
  WsClient(int port, const std::string& path, const std::vector<std::string>& headers = {}) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    const int one = 1;
    ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) return;
    std::string request = "GET " + path +
                          " HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\n"
                          "Connection: Upgrade\r\nSec-WebSocket-Key: " +
                          std::string(kKey) + "\r\n";
    bool version = false;
    for (const auto& h : headers) {
      request += h + "\r\n";
      version |= h.rfind("Sec-WebSocket-Version", 0) == 0;
    }
    if (!version) request += "Sec-WebSocket-Version: 13\r\n";
    request += "\r\n";
    SendRaw(request);
    // The response head, byte by byte so no frame is read with it.
    while (head_.find("\r\n\r\n") == std::string::npos) {
      char c;
      if (::recv(fd_, &c, 1, 0) != 1) break;
      head_ += c;
    }
    if (head_.size() > 12) status_ = std::atoi(head_.c_str() + 9);
    if (status_ != 101) {  // the error's JSON body follows
      const size_t at = Lower(head_).find("content-length:");
      if (at != std::string::npos) body_ = ReadExactly(std::stoul(head_.substr(at + 15)));
    }
  }
  ~WsClient() {
    if (fd_ >= 0) ::close(fd_);
  }

  int status() const { return status_; }
  std::string header(const std::string& name) const {
    const std::string lower = Lower(head_);
    const size_t at = lower.find("\r\n" + Lower(name) + ":");
    if (at == std::string::npos) return "";
    std::string value = head_.substr(at + name.size() + 3, head_.find("\r\n", at + 2) - (at + name.size() + 3));
    value.erase(0, value.find_first_not_of(' '));
    return value;
  }
  const std::string& body() const { return body_; }

  // A masked frame, as every client frame must be.
  void Send(int opcode, const std::string& payload, bool fin = true) {
    std::string f;
    f += static_cast<char>((fin ? 0x80 : 0) | opcode);
    const size_t n = payload.size();
    if (n < 126) {
      f += static_cast<char>(0x80 | n);
    } else if (n < 65536) {
      f += static_cast<char>(0x80 | 126);
      f += static_cast<char>(n >> 8);
      f += static_cast<char>(n & 0xff);
    } else {
      f += static_cast<char>(0x80 | 127);
      for (int s = 56; s >= 0; s -= 8) f += static_cast<char>((n >> s) & 0xff);
    }
    const uint32_t key = rng_();
    const char mask[4] = {static_cast<char>(key >> 24), static_cast<char>(key >> 16), static_cast<char>(key >> 8),
                          static_cast<char>(key)};
    f.append(mask, 4);
    for (size_t i = 0; i < n; ++i) f += static_cast<char>(payload[i] ^ mask[i % 4]);
    SendRaw(f);
  }
  void SendText(const std::string& s) { Send(0x1, s); }
  void SendClose(int code) { Send(0x8, std::string{static_cast<char>(code >> 8), static_cast<char>(code & 0xff)}); }

  // The next frame (server frames are never masked).
  Frame Receive(double seconds = 60) {
    Frame f;
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(seconds * 1000)) <= 0) return f;
    const std::string h = ReadExactly(2);
    if (h.size() < 2) return f;
    EXPECT_EQ(h[1] & 0x80, 0) << "a server frame was masked";
    EXPECT_TRUE(h[0] & 0x80) << "this server does not fragment";
    uint64_t n = h[1] & 0x7f;
    if (n == 126 || n == 127) {
      const std::string ext = ReadExactly(n == 126 ? 2 : 8);
      n = 0;
      for (unsigned char c : ext) n = (n << 8) | c;
    }
    f.payload = ReadExactly(static_cast<size_t>(n));
    f.opcode = h[0] & 0x0f;
    return f;
  }
  // True when the server closed the TCP connection within `seconds`.
  bool Closed(double seconds = 10) {
    pollfd p{fd_, POLLIN, 0};
    char c;
    return ::poll(&p, 1, static_cast<int>(seconds * 1000)) > 0 && ::recv(fd_, &c, 1, 0) <= 0;
  }
  void SendRaw(const std::string& bytes) { (void)!::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL); }

 private:
  static std::string Lower(std::string s) {
    for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  }
  std::string ReadExactly(size_t n) {
    std::string out(n, '\0');
    size_t got = 0;
    while (got < n) {
      const ssize_t r = ::recv(fd_, out.data() + got, n - got, 0);
      if (r <= 0) break;
      got += static_cast<size_t>(r);
    }
    out.resize(got);
    return out;
  }

  int fd_ = -1;
  int status_ = 0;
  std::string head_, body_;
  std::mt19937 rng_{42};
};

}  // namespace armature::testing
