#include <algorithm>
#include <charconv>
#include <cmath>
#include <numbers>
#include <string>
#include <unordered_set>
#include <vector>

#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/math/rotation.h"

namespace armature {
namespace {

constexpr double kRadianToDegree = 180.0 / std::numbers::pi;

// Six decimals: write → read reproduces angles to ~1e-8 rad and positions to
// 5e-7 units, far inside what any consumer can see.
void AppendFixed(std::string* out, double v) {
  char buf[400];  // the longest finite double in fixed notation has 309 digits before the point
  const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, 6);
  out->append(buf, r.ec == std::errc() ? r.ptr : buf);
}

void AppendShortest(std::string* out, double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  out->append(buf, r.ptr);
}

void AppendVector(std::string* out, const Eigen::Vector3d& v) {
  for (int k = 0; k < 3; ++k) {
    out->push_back(' ');
    AppendFixed(out, v[k]);
  }
}

std::vector<std::vector<Channel>> ChannelLists(const Skeleton& sk) {
  bool any = false;
  for (const auto& c : sk.channels) any = any || !c.empty();
  if (any) return sk.channels;
  std::vector<std::vector<Channel>> lists(sk.size());
  for (size_t i = 0; i < sk.size(); ++i) {
    if (sk.parents[i] < 0) lists[i] = {Channel::kXposition, Channel::kYposition, Channel::kZposition};
    lists[i].insert(lists[i].end(), {Channel::kZrotation, Channel::kXrotation, Channel::kYrotation});
  }
  return lists;
}

// Joints in depth-first pre-order: BVH lists motion columns in the order
// joints appear in the hierarchy, which other formats need not follow.
std::vector<size_t> DepthFirstOrder(const Skeleton& sk) {
  std::vector<std::vector<size_t>> children(sk.size());
  std::vector<size_t> stack;
  for (size_t i = 0; i < sk.size(); ++i) {
    if (sk.parents[i] < 0)
      stack.push_back(i);
    else
      children[static_cast<size_t>(sk.parents[i])].push_back(i);
  }
  std::reverse(stack.begin(), stack.end());
  std::vector<size_t> order;
  order.reserve(sk.size());
  while (!stack.empty()) {
    const size_t j = stack.back();
    stack.pop_back();
    order.push_back(j);
    for (auto it = children[j].rbegin(); it != children[j].rend(); ++it) stack.push_back(*it);
  }
  return order;
}

// Indentation stops growing past kMaxIndent so that the hierarchy of a deep
// chain costs linear, not quadratic, bytes (readers ignore whitespace).
constexpr size_t kMaxIndent = 32;
void Indent(std::string* out, size_t depth) { out->append(std::min(depth, kMaxIndent), '\t'); }

// Joint names as a BVH reader reads them back: the rest of the line after
// ROOT/JOINT, trimmed, with a trailing '{' taken for the block's brace. Names
// from other formats can hold anything: control characters become '_', blanks
// at the ends and a trailing '{' are avoided, and a name that then collides
// with another gets a "_<joint>" suffix.
std::vector<std::string> BvhNames(const Skeleton& sk) {
  std::vector<std::string> names(sk.size());
  std::unordered_set<std::string> used;
  for (size_t j = 0; j < sk.size(); ++j) {
    std::string n = sk.names[j];
    for (char& c : n)
      if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = '_';
    while (!n.empty() && n.front() == ' ') n.erase(0, 1);
    while (!n.empty() && n.back() == ' ') n.pop_back();
    if (n.empty() || n.back() == '{') n += "_";
    if (!used.insert(n).second) {
      n += '_';  // not "_" + std::to_string(j): GCC 12's false -Wrestrict on that operator+
      n += std::to_string(j);
      while (!used.insert(n).second) n += "_";
    }
    names[j] = std::move(n);
  }
  return names;
}

void WriteHierarchy(const Skeleton& sk, const std::vector<size_t>& order,
                    const std::vector<std::vector<Channel>>& channels, std::string* out) {
  const std::vector<std::string> names = BvhNames(sk);
  std::vector<size_t> open;  // joints whose block is not closed yet
  auto close = [&] {
    const size_t j = open.back();
    open.pop_back();
    const size_t depth = open.size();
    if (sk.end_sites[j]) {
      Indent(out, depth + 1);
      out->append("End Site\n");
      Indent(out, depth + 1);
      out->append("{\n");
      Indent(out, depth + 2);
      out->append("OFFSET");
      AppendVector(out, *sk.end_sites[j]);
      out->push_back('\n');
      Indent(out, depth + 1);
      out->append("}\n");
    }
    Indent(out, depth);
    out->append("}\n");
  };
  out->append("HIERARCHY\n");
  for (size_t j : order) {
    const int parent = sk.parents[j];
    while (!open.empty() && static_cast<int>(open.back()) != parent) close();
    const size_t depth = open.size();
    Indent(out, depth);
    out->append(parent < 0 ? "ROOT " : "JOINT ");
    out->append(names[j]);
    out->push_back('\n');
    Indent(out, depth);
    out->append("{\n");
    Indent(out, depth + 1);
    out->append("OFFSET");
    AppendVector(out, sk.rest[j].translation);
    out->push_back('\n');
    Indent(out, depth + 1);
    out->append("CHANNELS ");
    out->append(std::to_string(channels[j].size()));
    for (Channel c : channels[j]) {
      out->push_back(' ');
      out->append(ChannelName(c));
    }
    out->push_back('\n');
    open.push_back(j);
  }
  while (!open.empty()) close();
}

double ExportFrameTime(const Clip& clip) { return clip.frame_time > 0 ? clip.frame_time : 1.0 / 30.0; }

size_t ColumnCount(const std::vector<std::vector<Channel>>& channels) {
  size_t columns = 0;
  for (const auto& c : channels) columns += c.size();
  return columns;
}

}  // namespace

uint64_t BvhExportFrameCount(const Clip& clip) {
  if (clip.frame_time > 0 && clip.frame_count > 0) return clip.frame_count;
  const double frames = std::floor(clip.duration / ExportFrameTime(clip) + 1e-9) + 1;
  if (!(frames < 0x1p63)) return UINT64_MAX;  // also NaN
  return frames < 1 ? 1 : static_cast<uint64_t>(frames);
}

uint64_t BvhExportByteEstimate(const Clip& clip) {
  if (!clip.skeleton) return 0;
  const Skeleton& sk = *clip.skeleton;
  uint64_t hierarchy = 64;
  for (const std::string& name : sk.names) hierarchy += name.size() + kMaxIndent * 4 + 160;
  const uint64_t values = ColumnCount(ChannelLists(sk));
  uint64_t motion = 0;
  if (__builtin_mul_overflow(BvhExportFrameCount(clip), values * 11 + 1, &motion)) return UINT64_MAX;
  return hierarchy + motion;
}

StatusOr<std::string> ExportBvh(const Clip& clip, uint64_t max_frames) {
  if (!clip.skeleton || clip.joints.size() != clip.skeleton->size())
    return Status::InvalidArgument("clip has no skeleton or a track count that differs from its skeleton");
  const uint64_t frame_count = BvhExportFrameCount(clip);
  if (frame_count > max_frames)
    return Status::ResourceExhausted("BVH export would write " + std::to_string(frame_count) +
                                     " frames, over the limit of " + std::to_string(max_frames));
  const Skeleton& sk = *clip.skeleton;
  const std::vector<std::vector<Channel>> channels = ChannelLists(sk);
  const std::vector<size_t> order = DepthFirstOrder(sk);

  const double dt = ExportFrameTime(clip);
  const auto frames = static_cast<size_t>(frame_count);

  std::string out;
  out.reserve(2048 + frames * ColumnCount(channels) * 11);
  WriteHierarchy(sk, order, channels, &out);
  out.append("MOTION\nFrames: ");
  out.append(std::to_string(frames));
  out.append("\nFrame Time: ");
  AppendShortest(&out, dt);
  out.push_back('\n');

  // Per joint: its rotation axes and the previous frame's angles, the hint
  // that keeps Euler curves continuous instead of jumping by 2π.
  std::vector<std::vector<Axis>> axes(sk.size());
  std::vector<std::vector<double>> previous(sk.size()), angles(sk.size());
  for (size_t j = 0; j < sk.size(); ++j) {
    for (Channel c : channels[j])
      if (IsRotationChannel(c))
        axes[j].push_back(static_cast<Axis>(static_cast<int>(c) - static_cast<int>(Channel::kXrotation)));
    angles[j].resize(axes[j].size());
  }

  std::vector<Trs> pose(sk.size());
  for (size_t f = 0; f < frames; ++f) {
    ARMATURE_RETURN_IF_ERROR(SampleClip(clip, static_cast<double>(f) * dt, SampleOptions{}, pose));
    bool first_value = true;
    for (size_t j : order) {
      QuaternionToEuler(pose[j].rotation, axes[j], angles[j], previous[j]);
      size_t r = 0;
      for (Channel c : channels[j]) {
        double v;
        if (IsRotationChannel(c)) {
          v = angles[j][r++] * kRadianToDegree;
        } else {
          const int k = static_cast<int>(c) - static_cast<int>(Channel::kXposition);
          v = pose[j].translation[k] - sk.rest[j].translation[k];
        }
        if (!first_value) out.push_back(' ');
        first_value = false;
        AppendFixed(&out, v);
      }
      previous[j] = angles[j];
    }
    out.push_back('\n');
  }
  return out;
}

std::string WriteBvh(const Clip& clip) {
  auto text = ExportBvh(clip);
  return text.ok() ? std::move(*text) : std::string();
}

}  // namespace armature
