// A REST request's body read within its limit. An oversized body is still
// read (and dropped) up to kDrainBytes past the limit, so the connection
// stays in step for the next request; beyond that the client gets its 413
// and the connection is closed unread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace httplib {
struct Request;
struct Response;
class ContentReader;
}  // namespace httplib

namespace armature::server::gateway {

// How much of a refused body is still read (and dropped) past the limit.
inline constexpr size_t kDrainBytes = 64u << 20;

// "request body: <size> bytes exceed the limit of <limit> bytes (--max-upload-mb)"
// (or --max-request-kb when not `raw`).
std::string TooLarge(size_t size, size_t limit, bool raw);

// The body into `body` (from `reader`, or httplib's `req.body` when null), at
// most `limit` bytes; `declared` is its Content-Length. False once it has
// written the error (413 past the limit, 400 cut short).
bool ReadBoundedBody(const httplib::Request& req, const httplib::ContentReader* reader, size_t limit, uint64_t declared,
                     bool raw, httplib::Response& res, std::string* body);

}  // namespace armature::server::gateway
