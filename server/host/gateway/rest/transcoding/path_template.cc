#include "server/host/gateway/rest/transcoding/path_template.h"

#include <cctype>

namespace armature::server::gateway {
namespace {

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

StatusOr<std::string> PercentDecode(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] != '%') {
      out += s[i];
      continue;
    }
    const int hi = i + 2 < s.size() ? HexValue(s[i + 1]) : -1;
    const int lo = hi >= 0 ? HexValue(s[i + 2]) : -1;
    if (lo < 0) return Status::InvalidArgument("path: bad percent escape at '" + std::string(s.substr(i, 3)) + "'");
    out += static_cast<char>(hi * 16 + lo);
    i += 2;
  }
  return out;
}

bool IsIdentifier(std::string_view s) {
  if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

// Recursive-descent parser over the template text.
class Parser {
 public:
  explicit Parser(std::string_view text) : s_(text) {}

  Status Fail(const std::string& what) const {
    return Status::InvalidArgument("path template '" + std::string(s_) + "': " + what + " at column " +
                                   std::to_string(pos_ + 1));
  }
  bool AtEnd() const { return pos_ >= s_.size(); }
  char Peek() const { return AtEnd() ? '\0' : s_[pos_]; }
  bool Consume(char c) {
    if (Peek() != c) return false;
    ++pos_;
    return true;
  }
  // A literal runs up to the next '/', ':', '{', '}' or '='.
  std::string_view Literal() {
    const size_t start = pos_;
    while (!AtEnd() && std::string_view("/:{}=").find(s_[pos_]) == std::string_view::npos) ++pos_;
    return s_.substr(start, pos_ - start);
  }
  std::string_view Rest() {
    const auto r = s_.substr(pos_);
    pos_ = s_.size();
    return r;
  }

 private:
  std::string_view s_;
  size_t pos_ = 0;
};

}  // namespace

StatusOr<RequestPath> RequestPath::Parse(std::string_view target) {
  const std::string_view path = target.substr(0, target.find_first_of("?#"));
  if (path.empty() || path[0] != '/') return Status::InvalidArgument("path: must start with '/'");
  RequestPath out;
  size_t start = 1;
  while (true) {
    const size_t slash = path.find('/', start);
    auto decoded = PercentDecode(path.substr(start, slash == std::string_view::npos ? slash : slash - start));
    if (!decoded.ok()) return decoded.status();
    out.segments.push_back(std::move(*decoded));
    if (slash == std::string_view::npos) break;
    start = slash + 1;
  }
  return out;
}

StatusOr<PathTemplate> PathTemplate::Parse(std::string_view text) {
  PathTemplate t;
  t.text_ = std::string(text);
  Parser p(text);
  if (!p.Consume('/')) return p.Fail("must start with '/'");
  bool open = false;  // inside "{field=...}"
  Variable current;
  while (true) {
    bool segment_done = false;
    if (!open && p.Consume('{')) {
      const std::string_view field = p.Literal();
      for (size_t start = 0; start <= field.size();) {
        const size_t dot = std::min(field.find('.', start), field.size());
        if (!IsIdentifier(field.substr(start, dot - start)))
          return p.Fail("bad field path '" + std::string(field) + "'");
        start = dot + 1;
      }
      current = Variable{std::string(field), t.segments_.size(), 0};
      if (p.Consume('=')) {
        open = true;
      } else {  // {x} is {x=*}
        if (!p.Consume('}')) return p.Fail("expected '}'");
        t.segments_.push_back({Kind::kOne, ""});
        current.end = t.segments_.size();
        t.variables_.push_back(current);
        segment_done = true;
      }
    }
    if (!segment_done) {
      if (p.Consume('*')) {
        t.segments_.push_back({p.Consume('*') ? Kind::kAny : Kind::kOne, ""});
      } else {
        const std::string_view literal = p.Literal();
        if (literal.empty()) return p.Fail("empty segment");
        t.segments_.push_back({Kind::kLiteral, std::string(literal)});
      }
      if (open && p.Consume('}')) {
        current.end = t.segments_.size();
        t.variables_.push_back(current);
        open = false;
      }
    }
    if (p.Consume('/')) continue;
    if (open) return p.Fail("expected '}'");
    if (p.Consume(':')) {
      t.verb_ = std::string(p.Rest());
      if (t.verb_.empty() || t.verb_.find_first_of("/{}*") != std::string::npos) return p.Fail("bad verb");
    }
    if (!p.AtEnd()) return p.Fail("unexpected character");
    break;
  }
  for (size_t i = 0; i + 1 < t.segments_.size(); ++i)
    if (t.segments_[i].kind == Kind::kAny)
      return Status::InvalidArgument("path template '" + t.text_ + "': '**' must be last");
  return t;
}

bool PathTemplate::Match(const RequestPath& path, PathBindings* bindings) const {
  std::vector<std::string> segments = path.segments;
  if (!verb_.empty()) {
    std::string& last = segments.back();
    const std::string suffix = ":" + verb_;
    if (last.size() <= suffix.size() || last.compare(last.size() - suffix.size(), suffix.size(), suffix) != 0)
      return false;
    last.resize(last.size() - suffix.size());
  }
  return MatchSegments(segments, bindings);
}

bool PathTemplate::MatchSegments(const std::vector<std::string>& segments, PathBindings* bindings) const {
  const bool open_ended = !segments_.empty() && segments_.back().kind == Kind::kAny;
  if (open_ended ? segments.size() < segments_.size() - 1 : segments.size() != segments_.size()) return false;
  for (size_t i = 0; i < segments_.size(); ++i) {
    if (segments_[i].kind == Kind::kAny) break;
    if (segments[i].empty()) return false;
    if (segments_[i].kind == Kind::kLiteral && segments[i] != segments_[i].literal) return false;
  }
  bindings->clear();
  for (const Variable& v : variables_) {
    const size_t end = v.end == segments_.size() && open_ended ? segments.size() : v.end;
    std::string value;
    for (size_t i = v.begin; i < end; ++i) value += (i == v.begin ? "" : "/") + segments[i];
    bindings->emplace_back(v.field_path, std::move(value));
  }
  return true;
}

std::vector<std::string> PathTemplate::variables() const {
  std::vector<std::string> out;
  for (const auto& v : variables_) out.push_back(v.field_path);
  return out;
}

std::string PathTemplate::Simplified() const {
  std::string out;
  for (size_t i = 0; i < segments_.size();) {
    out += '/';
    const Variable* var = nullptr;
    for (const auto& v : variables_)
      if (v.begin == i) var = &v;
    if (var) {
      out += "{" + var->field_path + "}";
      i = std::max(var->end, i + 1);
      continue;
    }
    const Segment& s = segments_[i++];
    out += s.kind == Kind::kLiteral ? s.literal : s.kind == Kind::kOne ? "*" : "**";
  }
  if (!verb_.empty()) out += ":" + verb_;
  return out;
}

int PathTemplate::specificity() const {
  int score = verb_.empty() ? 0 : 1000;
  for (const auto& s : segments_) score += s.kind == Kind::kLiteral ? 10 : s.kind == Kind::kOne ? 1 : 0;
  return score;
}

}  // namespace armature::server::gateway
