// The bytes of one HTTP connection, plain or TLS, as cpp-httplib's Stream,
// on a non-blocking socket: every wait is a poll() bounded by the read or
// write timeout and, while a request head is being read, by the head's
// deadline. (httplib's own stream bounds each read alone, so a client that
// sends a byte every few seconds could hold a connection for ever, and an
// SSL_read on a blocking socket waits for a whole TLS record.)
#pragma once

#include <chrono>
#include <string>

#include <httplib.h>

namespace armature::server {

class ConnectionStream final : public httplib::Stream {
 public:
  using Clock = std::chrono::steady_clock;

  // `fd` must be non-blocking; `ssl` (may be null) is bound to it.
  ConnectionStream(int fd, SSL* ssl, std::chrono::milliseconds read_timeout, std::chrono::milliseconds write_timeout)
      : fd_(fd), ssl_(ssl), read_timeout_(read_timeout), write_timeout_(write_timeout) {}

  // Reads up to the end of the next request head (the empty line after the
  // headers) and the TLS handshake must be done by `deadline`.
  void ExpectHead(Clock::time_point deadline);
  // True once the head ExpectHead announced has been read whole.
  bool HeadDone() const { return !in_head_; }
  // True when the head being read ran past its deadline after some of it came.
  bool HeadTimedOut() const;
  // SSL_accept, under the head's deadline.
  bool AcceptTls();
  // Waits up to `timeout` for the first byte of a next request.
  bool WaitForRequest(std::chrono::milliseconds timeout) const;

  bool is_readable() const override;
  bool is_writable() const override;
  ssize_t read(char* ptr, size_t size) override;
  ssize_t write(const char* ptr, size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  socket_t socket() const override { return fd_; }

 private:
  // Waits for `events` on the socket for `timeout`, cut to the head's deadline while a head is read.
  bool Wait(short events, std::chrono::milliseconds timeout) const;
  // One recv or SSL_read into `ptr`, waiting as Wait does: >0 bytes, 0 closed, -1 error or timeout.
  ssize_t ReadSome(char* ptr, size_t size);
  // Follows the bytes handed to httplib to see where the head ends.
  void Note(const char* p, size_t n);

  int fd_;
  SSL* ssl_;
  std::chrono::milliseconds read_timeout_, write_timeout_;
  bool in_head_ = false;
  Clock::time_point head_deadline_;
  size_t head_bytes_ = 0;
  int head_end_matched_ = 0;  // how much of "\r\n\r\n" the latest bytes match
  char buffer_[4096];
  size_t begin_ = 0, end_ = 0;
};

}  // namespace armature::server
