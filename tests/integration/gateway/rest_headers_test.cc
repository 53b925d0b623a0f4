// The REST gateway answers from the headers alone when it should: no token
// (before reading an upload body), or an ambiguous body length; and the
// encodings it answers in.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>

#include <gtest/gtest.h>

#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

// Sends `head` (request line and headers, no body) and returns what the
// server answers before the client sends anything more (up to 10 s).
std::string AnswerToHeaders(int port, const std::string& head) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  ::inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return "";
  }
  timeval timeout{10, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  ::send(fd, head.data(), head.size(), 0);
  std::string answer;
  char buf[4096];
  for (ssize_t n; (n = ::recv(fd, buf, sizeof buf, 0)) > 0;) {
    answer.append(buf, static_cast<size_t>(n));
    if (answer.find("\r\n\r\n") != std::string::npos && answer.find('}') != std::string::npos) break;
  }
  ::close(fd);
  return answer;
}

TEST(RestHeaders, AnUploadWithoutATokenIsRefusedBeforeItsBody) {
  TempDir data, files;
  const auto tokens = WriteTemp(files, "tokens", "secret-token\n");
  ServerProcess server(data.path(), {"--no-demo", "--auth-token-file", tokens.string(), "--max-upload-mb", "512"});
  // 200 MB announced, none sent: the 401 comes from the headers alone.
  const std::string answer =
      AnswerToHeaders(server.http_port(),
                      "POST /v1/assets:import?filename=a.bvh HTTP/1.1\r\nHost: x\r\n"
                      "Content-Type: application/octet-stream\r\nContent-Length: 209715200\r\n\r\n");
  // AnswerToHeaders never sends a body byte: any answer at all came from the headers.
  EXPECT_EQ(answer.rfind("HTTP/1.1 401", 0), 0u) << answer;
  EXPECT_NE(answer.find("\"code\":16"), std::string::npos) << answer;  // UNAUTHENTICATED
  EXPECT_NE(answer.find("missing credentials"), std::string::npos) << answer;
}

TEST(RestHeaders, TwoContentLengthsAreABadRequest) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  const std::string answer =
      AnswerToHeaders(server.http_port(),
                      "POST /v1/clips/arm:evaluate HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
                      "Content-Length: 2\r\nContent-Length: 40\r\n\r\n");
  EXPECT_EQ(answer.rfind("HTTP/1.1 400", 0), 0u) << answer;
  EXPECT_NE(answer.find("Content-Length"), std::string::npos) << answer;
}

}  // namespace
}  // namespace armature::testing

namespace armature::testing {
namespace {

// The head of the answer to a GET with the given Accept-Encoding.
std::string HeadOfAnswer(int port, const std::string& path, const std::string& accept_encoding) {
  const std::string answer = AnswerToHeaders(port, "GET " + path + " HTTP/1.1\r\nHost: x\r\nConnection: close\r\n" +
                                                       "Accept-Encoding: " + accept_encoding + "\r\n\r\n");
  return answer.substr(0, answer.find("\r\n\r\n"));
}

// httplib would pick brotli at quality 11 (seconds for a megabyte of JSON):
// offered brotli is dropped, and the answer is gzip when gzip is offered too.
TEST(RestHeaders, BrowsersOfferingBrotliGetGzip) {
  TempDir data;
  ServerProcess server(data.path(), {});
  const std::string path = "/v1/meshes/demo_character.body:geometry";
  const std::string both = HeadOfAnswer(server.http_port(), path, "gzip, deflate, br");
  EXPECT_EQ(both.rfind("HTTP/1.1 200", 0), 0u) << both;
  EXPECT_NE(both.find("Content-Encoding: gzip"), std::string::npos) << both;
  const std::string brotli_only = HeadOfAnswer(server.http_port(), path, "br");
  EXPECT_EQ(brotli_only.rfind("HTTP/1.1 200", 0), 0u) << brotli_only;
  EXPECT_EQ(brotli_only.find("Content-Encoding"), std::string::npos) << brotli_only;
}

}  // namespace
}  // namespace armature::testing
