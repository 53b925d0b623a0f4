// A google.api.http path template, e.g. "/v1/clips/{clip}:evaluate" or
// "/v1/{name=assets/*}", parsed once and matched against request paths.
//
//   Template = "/" Segments [ ":" Verb ]
//   Segment  = "*" | "**" | LITERAL | "{" FieldPath [ "=" Segments ] "}"
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "armature/base/status.h"

namespace armature::server::gateway {

// A request path split the way templates see it: percent-decoded segments
// and the raw last segment (which may end in ":verb").
struct RequestPath {
  std::vector<std::string> segments;  // decoded; the last one still holds any ":verb"
  // Splits the path part of a request target ("/v1/clips/a%20b:evaluate?x=1").
  // INVALID_ARGUMENT for a bad percent escape.
  static StatusOr<RequestPath> Parse(std::string_view target);
};

using PathBindings = std::vector<std::pair<std::string, std::string>>;  // field path → value

class PathTemplate {
 public:
  static StatusOr<PathTemplate> Parse(std::string_view text);

  // True when `path` matches; fills `bindings` with the variables' values
  // (multi-segment variables joined with '/').
  bool Match(const RequestPath& path, PathBindings* bindings) const;

  const std::string& text() const { return text_; }
  const std::string& verb() const { return verb_; }
  // The variables' field paths, in order.
  std::vector<std::string> variables() const;
  // The template with each variable reduced to "{field.path}" (OpenAPI style).
  std::string Simplified() const;
  // Literal segments count for more than wildcards when two templates match.
  int specificity() const;

 private:
  enum class Kind { kLiteral, kOne, kAny };  // "lit", "*", "**"
  struct Segment {
    Kind kind;
    std::string literal;
  };
  struct Variable {
    std::string field_path;
    size_t begin = 0, end = 0;  // its segments: [begin, end)
  };
  bool MatchSegments(const std::vector<std::string>& segments, PathBindings* bindings) const;

  std::string text_;
  std::vector<Segment> segments_;
  std::vector<Variable> variables_;
  std::string verb_;
};

}  // namespace armature::server::gateway
