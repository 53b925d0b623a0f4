// BVH reader: a hand-written scanner over the bytes (string_view tokens,
// std::from_chars numbers) because mocap files are megabytes of numbers and
// iostreams would spend most of the time on locale and allocation. Frame
// lines, nearly all of the bytes, are read in one pass with a fast path for
// plain decimals (plain_decimal.h) and inlined Euler angles (euler_degrees.h).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/math/rotation.h"
#include "armature/base/utf8.h"
#include "euler_degrees.h"
#include "plain_decimal.h"

namespace armature {
namespace {

constexpr int kMaxChannelsPerJoint = 64;

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

char Lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

bool EqualsIgnoreCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (Lower(a[i]) != Lower(b[i])) return false;
  return true;
}

bool StartsWithIgnoreCase(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && EqualsIgnoreCase(s.substr(0, prefix.size()), prefix);
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && IsSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && IsSpace(s.back())) s.remove_suffix(1);
  return s;
}

// Input quoted for a message: cut short, bytes that are not UTF-8 escaped.
std::string Quoted(std::string_view token) {
  if (token.empty()) return "end of file";
  // Appended in place: GCC 12 warns (-Wrestrict, a false positive) on "'" + std::string&&.
  std::string quoted = "'";
  quoted += EscapeForMessage(token, 40);
  quoted += '\'';
  return quoted;
}

std::optional<Channel> ParseChannel(std::string_view s) {
  for (Channel c : {Channel::kXposition, Channel::kYposition, Channel::kZposition, Channel::kXrotation,
                    Channel::kYrotation, Channel::kZrotation})
    if (EqualsIgnoreCase(s, ChannelName(c))) return c;
  return std::nullopt;
}

// A number as BVH writers print it: from_chars plus an optional leading '+'.
// Returns false unless all of `s` is one number.
bool ParseDouble(std::string_view s, double* out) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), *out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

bool ParseCount(std::string_view s, long long* out) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), *out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

// Splits the text into whitespace-separated tokens ('{' and '}' always stand
// alone) and whole lines, counting lines as it goes.
class Scanner {
 public:
  explicit Scanner(std::string_view text) : text_(text) {}

  // The next token, or empty at the end of the text.
  std::string_view Next() {
    SkipSpace();
    token_line_ = line_;
    if (pos_ >= text_.size()) return {};
    const size_t start = pos_;
    if (text_[pos_] == '{' || text_[pos_] == '}') return text_.substr(pos_++, 1);
    while (pos_ < text_.size() && !IsSpace(text_[pos_]) && text_[pos_] != '{' && text_[pos_] != '}') ++pos_;
    return text_.substr(start, pos_ - start);
  }

  // The rest of the current line, trimmed, with a trailing '{' split off
  // (`*brace` tells whether there was one).
  std::string_view LineTail(bool* brace) {
    const size_t start = pos_;
    while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    std::string_view tail = Trim(text_.substr(start, pos_ - start));
    *brace = !tail.empty() && tail.back() == '{';
    if (*brace) tail = Trim(tail.substr(0, tail.size() - 1));
    return tail;
  }

  // Skips to the start of the next line that is not blank and returns it
  // without its line break; empty at the end of the text.
  std::string_view NextLine() {
    for (;;) {
      while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;  // rest of the current line
      if (pos_ >= text_.size()) {
        token_line_ = line_;
        return {};
      }
      ++pos_;
      ++line_;
      const size_t start = pos_;
      while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
      const std::string_view line = text_.substr(start, pos_ - start);
      pos_ = start;
      token_line_ = line_;
      if (!Trim(line).empty()) return line;
    }
  }

  int token_line() const { return token_line_; }
  size_t remaining() const { return text_.size() - pos_; }
  std::string_view text() const { return text_; }
  size_t pos() const { return pos_; }
  // Continues at `pos`, which is on line `line` (for a reader that scanned
  // the text itself).
  void Seek(size_t pos, int line) {
    pos_ = pos;
    line_ = line;
    token_line_ = line;
  }
  int line() const { return line_; }

 private:
  void SkipSpace() {
    while (pos_ < text_.size() && IsSpace(text_[pos_])) {
      if (text_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }

  std::string_view text_;
  size_t pos_ = 0;
  int line_ = 1;
  int token_line_ = 1;
};

struct JointDef {
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  std::vector<Channel> channels;
  std::vector<Axis> rotation_axes;         // rotation channels in order
  std::vector<int> rotation_columns;       // their columns in a frame line
  int position_columns[3] = {-1, -1, -1};  // x, y, z (−1: none)
  bool has_position = false;
};

// The line break that ends the line `p` is on, or `end`.
const char* LineEnd(const char* p, const char* end) {
  const void* nl = std::memchr(p, '\n', static_cast<size_t>(end - p));
  return nl != nullptr ? static_cast<const char*>(nl) : end;
}

class BvhParser {
 public:
  BvhParser(std::string_view text, const ImportLimits& limits) : scan_(text), limits_(limits) {}

  StatusOr<BvhData> Parse() {
    ARMATURE_RETURN_IF_ERROR(Expect("HIERARCHY"));
    std::string_view tok = scan_.Next();
    if (!EqualsIgnoreCase(tok, "ROOT")) return Error("expected ROOT, found " + Quoted(tok));
    while (EqualsIgnoreCase(tok, "ROOT")) {
      ARMATURE_RETURN_IF_ERROR(ParseRoot());
      tok = scan_.Next();
    }
    if (!EqualsIgnoreCase(tok, "MOTION")) return Error("expected ROOT or MOTION, found " + Quoted(tok));
    ARMATURE_RETURN_IF_ERROR(ParseMotion());
    skeleton_->channels.reserve(joints_.size());
    for (JointDef& j : joints_) skeleton_->channels.push_back(j.channels);
    ARMATURE_RETURN_IF_ERROR(skeleton_->Validate());
    clip_->skeleton = skeleton_;
    ARMATURE_RETURN_IF_ERROR(clip_->Validate());
    return BvhData{skeleton_, clip_, std::move(warnings_)};
  }

 private:
  Status Error(const std::string& message) const { return ErrorAt(scan_.token_line(), message); }
  static Status ErrorAt(int line, const std::string& message) {
    return Status::InvalidArgument("line " + std::to_string(line) + ": " + message);
  }

  Status Expect(std::string_view keyword) {
    const std::string_view tok = scan_.Next();
    if (!EqualsIgnoreCase(tok, keyword)) return Error("expected " + std::string(keyword) + ", found " + Quoted(tok));
    return Status::Ok();
  }

  Status ExpectOpenBrace(bool brace_on_name_line) {
    if (brace_on_name_line) return Status::Ok();
    return Expect("{");
  }

  Status ReadNumber(std::string_view what, double* out) {
    const std::string_view tok = scan_.Next();
    if (!ParseDouble(tok, out)) return Error("expected a number for " + std::string(what) + ", found " + Quoted(tok));
    if (!std::isfinite(*out)) return Error(std::string(what) + " value " + Quoted(tok) + " is not finite");
    return Status::Ok();
  }

  Status ReadOffset(Eigen::Vector3d* offset) {
    ARMATURE_RETURN_IF_ERROR(Expect("OFFSET"));
    for (int k = 0; k < 3; ++k) ARMATURE_RETURN_IF_ERROR(ReadNumber("OFFSET", &(*offset)[k]));
    return Status::Ok();
  }

  // ROOT or JOINT header: name, '{', OFFSET, optional CHANNELS. Returns the
  // next token (the first of the body) in `*next`.
  Status ParseJointHeader(int parent, std::string_view* next) {
    const int name_line = scan_.token_line();
    bool brace = false;
    const std::string_view name = scan_.LineTail(&brace);
    if (name.empty()) return Error("joint has no name");
    // Names travel in protobuf strings, which must be UTF-8.
    if (!IsValidUtf8(name)) return Error("joint name " + Quoted(name) + " is not valid UTF-8");
    std::string name_str(name);
    if (auto [it, inserted] = name_lines_.emplace(name_str, name_line); !inserted)
      return Error("duplicate joint name " + Quoted(name_str) + " (first on line " + std::to_string(it->second) + ")");
    ARMATURE_RETURN_IF_ERROR(ExpectOpenBrace(brace));

    JointDef def;
    ARMATURE_RETURN_IF_ERROR(ReadOffset(&def.offset));
    std::string_view tok = scan_.Next();
    if (EqualsIgnoreCase(tok, "CHANNELS")) {
      ARMATURE_RETURN_IF_ERROR(ReadChannels(&def));
      tok = scan_.Next();
    }
    skeleton_->names.push_back(std::move(name_str));
    skeleton_->parents.push_back(parent);
    Trs rest;
    rest.translation = def.offset;
    skeleton_->rest.push_back(rest);
    skeleton_->end_sites.emplace_back();
    joints_.push_back(std::move(def));
    *next = tok;
    return Status::Ok();
  }

  Status ReadChannels(JointDef* def) {
    const int channels_line = scan_.token_line();
    const std::string_view count_tok = scan_.Next();
    long long count = 0;
    if (!ParseCount(count_tok, &count) || count < 0 || count > kMaxChannelsPerJoint)
      return Error("channel count " + Quoted(count_tok) + " is not a whole number from 0 to " +
                   std::to_string(kMaxChannelsPerJoint));
    for (long long c = 0; c < count; ++c) {
      const std::string_view tok = scan_.Next();
      const std::optional<Channel> ch = ParseChannel(tok);
      if (!ch) {
        // A count that disagrees with the names is the CHANNELS line's fault;
        // a misspelt name is the fault of the line it is on.
        if (scan_.token_line() == channels_line && !tok.empty())
          return Error("unknown channel " + Quoted(tok) +
                       " (expected Xposition, Yposition, Zposition, Xrotation, Yrotation or Zrotation)");
        return ErrorAt(channels_line, "CHANNELS declares " + std::to_string(count) + " channels but lists " +
                                          std::to_string(c) + " (next is " + Quoted(tok) + " on line " +
                                          std::to_string(scan_.token_line()) + ")");
      }
      const int column = total_channels_++;
      def->channels.push_back(*ch);
      if (IsRotationChannel(*ch)) {
        def->rotation_axes.push_back(static_cast<Axis>(static_cast<int>(*ch) - static_cast<int>(Channel::kXrotation)));
        def->rotation_columns.push_back(column);
      } else {
        const int axis = static_cast<int>(*ch) - static_cast<int>(Channel::kXposition);
        if (def->position_columns[axis] >= 0)
          return Error("channel " + std::string(ChannelName(*ch)) + " is listed twice for one joint");
        def->position_columns[axis] = column;
        def->has_position = true;
      }
    }
    return Status::Ok();
  }

  // One ROOT block with everything below it; iterative so that deep nesting
  // in a hostile file cannot overflow the stack.
  Status ParseRoot() {
    std::vector<int> open;  // joints whose '}' is still to come
    std::string_view tok;
    ARMATURE_RETURN_IF_ERROR(ParseJointHeader(-1, &tok));
    open.push_back(static_cast<int>(joints_.size()) - 1);
    for (;;) {
      const int current = open.back();
      if (EqualsIgnoreCase(tok, "JOINT")) {
        ARMATURE_RETURN_IF_ERROR(ParseJointHeader(current, &tok));
        open.push_back(static_cast<int>(joints_.size()) - 1);
        continue;
      }
      if (EqualsIgnoreCase(tok, "End")) {
        bool brace = false;
        const std::string_view site = scan_.LineTail(&brace);
        if (!StartsWithIgnoreCase(site, "Site"))
          return Error("expected 'End Site', found " + Quoted("End " + std::string(site)));
        ARMATURE_RETURN_IF_ERROR(ExpectOpenBrace(brace));
        Eigen::Vector3d offset;
        ARMATURE_RETURN_IF_ERROR(ReadOffset(&offset));
        ARMATURE_RETURN_IF_ERROR(Expect("}"));
        auto& end_site = skeleton_->end_sites[static_cast<size_t>(current)];
        if (!end_site) end_site = offset;  // a second End Site on one joint is rare; the first one wins
      } else if (tok == "}") {
        open.pop_back();
        if (open.empty()) return Status::Ok();
      } else if (tok.empty()) {
        return Error("file ends inside joint '" + skeleton_->names[static_cast<size_t>(current)] + "' (missing '}')");
      } else {
        return Error("expected JOINT, End Site or '}' in joint '" + skeleton_->names[static_cast<size_t>(current)] +
                     "', found " + Quoted(tok));
      }
      tok = scan_.Next();
    }
  }

  // "Frames: N" / "Frame Time: T": a label (words separated by blanks), a
  // colon, one number.
  Status ReadLabeledLine(std::initializer_list<std::string_view> words, std::string_view* value) {
    const std::string_view line = scan_.NextLine();
    const std::string expected = words.size() == 1 ? "'Frames: <count>'" : "'Frame Time: <seconds>'";
    std::string_view rest = Trim(line);
    for (std::string_view w : words) {
      if (!StartsWithIgnoreCase(rest, w)) return Error("expected " + expected + ", found " + Quoted(Trim(line)));
      rest = Trim(rest.substr(w.size()));
    }
    if (rest.empty() || rest.front() != ':') return Error("expected " + expected + ", found " + Quoted(Trim(line)));
    *value = Trim(rest.substr(1));
    return Status::Ok();
  }

  // The MOTION header: "Frames: n" and "Frame Time: seconds".
  struct MotionHeader {
    long long frames = 0;
    int frames_line = 0;  // the line of "Frames:", for messages
    double dt = 0;
  };

  StatusOr<MotionHeader> ReadMotionHeader() {
    MotionHeader header;
    std::string_view value;
    ARMATURE_RETURN_IF_ERROR(ReadLabeledLine({"Frames"}, &value));
    if (!ParseCount(value, &header.frames) || header.frames < 0)
      return Error("frame count " + Quoted(value) + " is not a whole number >= 0");
    header.frames_line = scan_.token_line();
    const auto frame_count = static_cast<uint64_t>(header.frames);
    if (frame_count > limits_.max_clip_frames)
      return Status::ResourceExhausted(
          "line " + std::to_string(header.frames_line) + ": " +
          OverImportLimitCount(frame_count, "frames (Frames:)", "max_clip_frames", limits_.max_clip_frames));
    ARMATURE_RETURN_IF_ERROR(ReadLabeledLine({"Frame", "Time"}, &value));
    if (!ParseDouble(value, &header.dt) || !std::isfinite(header.dt) || !(header.dt > 0))
      return Error("frame time " + Quoted(value) + " is not a positive number of seconds");
    return header;
  }

  // The clip, its tracks' keys bounded by max_clip_keys and reserved; returns
  // the frames reserved.
  StatusOr<size_t> StartClip(const MotionHeader& header) {
    // Tracks only for joints with channels: a joint without any stays at its
    // rest pose, and no key is stored that no bytes of the file pay for.
    const auto frame_count = static_cast<uint64_t>(header.frames);
    size_t tracks = 0;
    for (const JointDef& def : joints_) tracks += (def.rotation_axes.empty() ? 0 : 1) + (def.has_position ? 1 : 0);
    uint64_t keys = 0;
    if (__builtin_mul_overflow(frame_count, tracks, &keys)) keys = UINT64_MAX;
    if (keys > limits_.max_clip_keys)
      return Status::ResourceExhausted(
          "line " + std::to_string(header.frames_line) + ": " +
          OverImportLimit(std::to_string(frame_count) + " frames × " + std::to_string(tracks) + " tracks =", keys,
                          "max_clip_keys", limits_.max_clip_keys));
    clip_ = std::make_shared<Clip>();
    clip_->joints.resize(joints_.size());
    clip_->frame_time = header.dt;
    clip_->frame_count = static_cast<size_t>(header.frames);
    clip_->duration = header.frames > 0 ? static_cast<double>(header.frames - 1) * header.dt : 0.0;
    clip_->default_interpolation = Interpolation::kLinear;

    // Reserve no more frames than the rest of the file can hold (each value
    // takes two bytes at least), so a lying frame count cannot make us
    // allocate gigabytes.
    const size_t columns = static_cast<size_t>(total_channels_);
    const size_t capacity = std::min<size_t>(static_cast<size_t>(header.frames),
                                             scan_.remaining() / (2 * std::max<size_t>(columns, 1)) + 1);
    for (size_t j = 0; j < joints_.size(); ++j) {
      if (!joints_[j].rotation_axes.empty()) clip_->joints[j].rotation.values.reserve(capacity);
      if (joints_[j].has_position) clip_->joints[j].translation.values.reserve(capacity);
    }
    return capacity;
  }

  Status ParseMotion() {
    ARMATURE_ASSIGN_OR_RETURN(const MotionHeader header, ReadMotionHeader());
    ARMATURE_ASSIGN_OR_RETURN(const size_t capacity, StartClip(header));
    std::vector<double> times;
    times.reserve(capacity);
    ARMATURE_RETURN_IF_ERROR(ReadFrames(header, times));
    WarnExtraLines(header.frames);
    for (size_t j = 0; j < joints_.size(); ++j) {
      JointTrack& track = clip_->joints[j];
      if (!joints_[j].rotation_axes.empty()) {
        track.rotation.times = times;
        track.rotation.interpolation = Interpolation::kLinear;
      }
      if (joints_[j].has_position) {
        track.translation.times = times;
        track.translation.interpolation = Interpolation::kLinear;
      }
    }
    return Status::Ok();
  }

  // Frame lines in one pass over the bytes: no line is scanned twice, and
  // plain decimals take plain_decimal.h's fast path.
  Status ReadFrames(const MotionHeader& header, std::vector<double>& times) {
    const size_t columns = static_cast<size_t>(total_channels_);
    std::vector<double> row(columns);
    const std::string_view text = scan_.text();
    const char* p = LineEnd(text.data() + scan_.pos(), text.data() + text.size());  // past "Frame Time:"
    const char* const end = text.data() + text.size();
    int line = scan_.line();
    for (long long f = 0; f < header.frames; ++f) {
      size_t count = 0;
      while (count == 0) {  // blank lines hold no frame
        if (p >= end) {
          scan_.Seek(text.size(), line);
          return Error("file ends after " + std::to_string(f) + " of the " + std::to_string(header.frames) +
                       " frames that 'Frames:' on line " + std::to_string(header.frames_line) + " declares");
        }
        ++p;  // the line break
        ++line;
        ARMATURE_RETURN_IF_ERROR(ReadFrameValues(&p, end, line, f, &row, &count));
      }
      if (count != columns)
        return ErrorAt(line, "frame " + std::to_string(f) + " has " + std::to_string(count) + " values, expected " +
                                 std::to_string(columns));
      times.push_back(static_cast<double>(f) * header.dt);
      AppendFrame(row);
    }
    scan_.Seek(static_cast<size_t>(p - text.data()), line);
    return Status::Ok();
  }

  // One frame's values (`row`, by column) as each joint's keys.
  void AppendFrame(const std::vector<double>& row) {
    for (size_t j = 0; j < joints_.size(); ++j) {
      const JointDef& def = joints_[j];
      JointTrack& track = clip_->joints[j];
      if (!def.rotation_axes.empty())
        track.rotation.values.push_back(bvh_detail::EulerDegreesToQuaternion(
            def.rotation_axes.data(), def.rotation_columns.data(), def.rotation_axes.size(), row.data()));
      if (def.has_position) {
        Eigen::Vector3d t = def.offset;
        for (int k = 0; k < 3; ++k)
          if (def.position_columns[k] >= 0) t[k] += row[static_cast<size_t>(def.position_columns[k])];
        track.translation.values.push_back(t);
      }
    }
  }

  // Lines beyond the declared count are ignored, as three.js, assimp and
  // Blender do (real exporters write one too many).
  void WarnExtraLines(long long frames) {
    std::string_view extra = scan_.NextLine();
    if (extra.empty()) return;
    const int first_extra = scan_.token_line();
    size_t count = 0;
    for (; !extra.empty(); extra = scan_.NextLine()) ++count;
    warnings_.push_back("line " + std::to_string(first_extra) + ": " + std::to_string(count) + " frame line" +
                        (count == 1 ? "" : "s") + " beyond Frames: " + std::to_string(frames) + " ignored");
  }

  // The values of the frame line that starts at `*p`, up to its line break
  // (left for the caller) or the end of the text, into `row` (counted in
  // `*count`, also beyond the row so that the message can say how many).
  Status ReadFrameValues(const char** p, const char* end, int line, long long frame, std::vector<double>* row,
                         size_t* count) const {
    const char* q = *p;
    for (;;) {
      while (q < end && *q != '\n' && IsSpace(*q)) ++q;
      if (q >= end || *q == '\n') break;
      double v = 0;
      const char* number_end = io_detail::ParsePlainDecimal(q, end, &v);
      if (number_end == nullptr || (number_end < end && !IsSpace(*number_end))) {
        number_end = q;
        while (number_end < end && !IsSpace(*number_end)) ++number_end;
        const std::string_view tok(q, static_cast<size_t>(number_end - q));
        if (!ParseDouble(tok, &v))
          return ErrorAt(line, "frame " + std::to_string(frame) + " value " + std::to_string(*count + 1) + " " +
                                   Quoted(tok) + " is not a number");
        if (!std::isfinite(v))
          return ErrorAt(line, "frame " + std::to_string(frame) + " value " + std::to_string(*count + 1) + " " +
                                   Quoted(tok) + " is not finite");
      }
      if (*count < row->size()) (*row)[*count] = v;
      ++*count;
      q = number_end;
    }
    *p = q;
    return Status::Ok();
  }

  Scanner scan_;
  std::shared_ptr<Skeleton> skeleton_ = std::make_shared<Skeleton>();
  std::shared_ptr<Clip> clip_;
  std::vector<JointDef> joints_;
  std::unordered_map<std::string, int> name_lines_;
  int total_channels_ = 0;
  const ImportLimits& limits_;
  std::vector<std::string> warnings_;
};

}  // namespace

StatusOr<BvhData> ParseBvh(std::string_view text, const ImportLimits& limits) {
  return BvhParser(text, limits).Parse();
}

}  // namespace armature
