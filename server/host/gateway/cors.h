// Cross-origin access for the origins given by --cors-origin ("*": any).
// Allowed origins get Access-Control-* headers on every response and their
// preflight (OPTIONS) requests answered; other origins get no CORS headers,
// so browsers keep them out. Same-origin pages (the viewer) need none.
#pragma once

#include <string>
#include <vector>

namespace httplib {
struct Request;
struct Response;
}  // namespace httplib

namespace armature::server::gateway {

class CorsPolicy {
 public:
  explicit CorsPolicy(std::vector<std::string> origins);

  bool Allows(const std::string& origin) const;
  // Adds the CORS headers to an ordinary response when its origin is allowed.
  void Decorate(const httplib::Request& req, httplib::Response& res) const;
  // Answers an OPTIONS request: a CORS preflight (204 for an allowed origin,
  // 403 otherwise) or a plain OPTIONS (204 with Allow).
  void AnswerOptions(const httplib::Request& req, httplib::Response& res, const std::string& allowed_methods) const;

 private:
  std::vector<std::string> origins_;
  bool any_ = false;
};

}  // namespace armature::server::gateway
