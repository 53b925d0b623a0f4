#include "armature/engine/anim/crowd/crowd_ticker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <string>
#include <utility>

#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/crowd/crowd_schedule.h"

namespace armature {
namespace {

std::string Named(uint32_t id) { return "character " + std::to_string(id) + ": "; }

uint64_t ShareHash(uint32_t clip, int64_t step) {
  uint64_t h = (static_cast<uint64_t>(clip) + 1) * 0x9E3779B97F4A7C15ull;
  h ^= static_cast<uint64_t>(step) * 0xC2B2AE3D27D4EB4Full;
  return h ^ (h >> 29);
}

}  // namespace

CrowdTicker::CrowdTicker(CrowdTickOptions options) : options_(options) {
  options_.max_interval = std::clamp<uint32_t>(options_.max_interval, 1, 255);
}

StatusOr<uint32_t> CrowdTicker::AddClip(std::shared_ptr<const CompressedClip> clip) {
  if (!clip) return Status::InvalidArgument("crowd: no clip");
  for (size_t i = 0; i < clips_.size(); ++i)
    if (clips_[i].clip == clip) return static_cast<uint32_t>(i);
  ARMATURE_ASSIGN_OR_RETURN(PoseLayout layout, LayoutOfClip(*clip));
  max_joints_ = std::max<size_t>(max_joints_, layout.joints);
  max_pose_bytes_ = std::max(max_pose_bytes_, layout.EncodedSize());
  scratch_.resize(10 * max_joints_);
  motion_scratch_.resize(max_joints_);
  ClipSamplingContext context(*clip);
  clips_.push_back({std::move(clip), std::move(layout), std::move(context), nullptr});
  return static_cast<uint32_t>(clips_.size() - 1);
}

Status CrowdTicker::Check(const CrowdCharacter& c) const {
  if (c.clip >= clips_.size()) return Status::InvalidArgument(Named(c.id) + "unknown clip " + std::to_string(c.clip));
  if (!std::isfinite(c.time_offset)) return Status::InvalidArgument(Named(c.id) + "time_offset is not finite");
  if (!std::isfinite(c.speed)) return Status::InvalidArgument(Named(c.id) + "speed is not finite");
  if (!std::isfinite(c.significance)) return Status::InvalidArgument(Named(c.id) + "significance is not finite");
  return Status::Ok();
}

Status CrowdTicker::Add(const CrowdCharacter& character) {
  if (Has(character.id)) return Status::InvalidArgument(Named(character.id) + "the id is already in the crowd");
  ARMATURE_RETURN_IF_ERROR(Check(character));
  slot_of_.emplace(character.id, static_cast<uint32_t>(characters_.size()));
  characters_.push_back(character);
  intervals_.push_back(1);
  last_tick_.push_back(-1);
  Grow();
  rank_dirty_ = true;
  return Status::Ok();
}

Status CrowdTicker::Update(const CrowdCharacter& character) {
  auto it = slot_of_.find(character.id);
  if (it == slot_of_.end()) return Status::InvalidArgument(Named(character.id) + "no such id in the crowd");
  ARMATURE_RETURN_IF_ERROR(Check(character));
  CrowdCharacter& c = characters_[it->second];
  if (c.significance != character.significance) rank_dirty_ = true;
  c = character;
  return Status::Ok();
}

Status CrowdTicker::Remove(uint32_t id) {
  auto it = slot_of_.find(id);
  if (it == slot_of_.end()) return Status::InvalidArgument(Named(id) + "no such id in the crowd");
  const uint32_t slot = it->second, last = static_cast<uint32_t>(characters_.size() - 1);
  slot_of_.erase(it);
  if (slot != last) {  // the last slot moves into the hole
    characters_[slot] = characters_[last];
    intervals_[slot] = intervals_[last];
    last_tick_[slot] = last_tick_[last];
    slot_of_[characters_[slot].id] = slot;
  }
  characters_.pop_back();
  intervals_.pop_back();
  last_tick_.pop_back();
  rank_dirty_ = true;
  return Status::Ok();
}

void CrowdTicker::Grow() {
  ranked_.reserve(characters_.size());
  due_.resize(characters_.size());
  order_.reserve(characters_.size());
  size_t want = 16;
  while (want < 2 * characters_.size()) want *= 2;
  if (shared_.size() < want) shared_.assign(want, ShareEntry{});
}

double CrowdTicker::ClipTime(const CrowdCharacter& c, double time, int64_t* step) const {
  const double duration = clips_[c.clip].clip->duration;
  double t = WrapTime(c.time_offset + c.speed * time, duration, WrapMode::kLoop);
  if (options_.share_quantum > 0) {
    *step = std::llround(t / options_.share_quantum);
    t = WrapTime(static_cast<double>(*step) * options_.share_quantum, duration, WrapMode::kLoop);
  }
  return t;
}

const CrowdTicker::ShareEntry* CrowdTicker::FindOrInsertShared(uint32_t clip, int64_t step, size_t offset) {
  const size_t mask = shared_.size() - 1;
  for (size_t i = ShareHash(clip, step) & mask;; i = (i + 1) & mask) {
    ShareEntry& e = shared_[i];
    if (e.generation != generation_) {
      e = {generation_, clip, step, offset};
      return &e;
    }
    if (e.clip == clip && e.step == step) return &e;
  }
}

Status CrowdTicker::Tick(uint64_t tick, double time, CrowdTick* out) {
  if (rank_dirty_) {
    ranked_.resize(characters_.size());
    for (uint32_t i = 0; i < ranked_.size(); ++i) ranked_[i] = i;
    std::sort(ranked_.begin(), ranked_.end(), [&](uint32_t a, uint32_t b) {
      const CrowdCharacter &x = characters_[a], &y = characters_[b];
      return x.significance != y.significance ? x.significance > y.significance : x.id < y.id;
    });
    rank_dirty_ = false;
  }
  const double cost = options_.fixed_cost_us > 0 ? options_.fixed_cost_us : cost_us_;
  const double capacity = options_.budget_us / cost;
  out->tick = tick;
  out->time = time;
  out->cost_us = cost;
  out->reduced = AssignIntervals(ranked_, capacity, options_.max_interval, intervals_);
  const size_t cap = static_cast<size_t>(std::max(1.0, std::ceil(capacity)));
  const size_t count = SelectDue(ranked_, {intervals_, last_tick_}, static_cast<int64_t>(tick), cap, due_);
  out->deferred = characters_.size() - count;
  out->ids.resize(count);
  out->clips.resize(count);
  out->clip_times.resize(count);
  out->poses.resize(count * max_pose_bytes_);
  ++generation_;
  const auto start = std::chrono::steady_clock::now();
  // Each pose's place in the output follows the schedule's order. Sharing
  // picks the poses to sample (the first of each clip and quantized time);
  // they are sampled by clip and clip time, so characters in one segment
  // follow one another and its header is read once (the context per clip);
  // the others are copied from theirs afterwards.
  constexpr size_t kSampled = static_cast<size_t>(-1), kWritten = static_cast<size_t>(-2);
  offsets_.resize(count);
  copy_from_.resize(count);
  order_.clear();
  size_t offset = 0, samples = 0;
  for (size_t i = 0; i < count; ++i) {
    const CrowdCharacter& c = characters_[due_[i]];
    if (clips_[c.clip].motion) {  // its own path (crowd_ticker_motion.cc), written at once
      offsets_[i] = offset;
      copy_from_[i] = kWritten;
      ARMATURE_RETURN_IF_ERROR(TickMotion(c, time, i, out, &offset, &samples));
      continue;
    }
    int64_t step = 0;
    out->ids[i] = c.id;
    out->clips[i] = c.clip;
    out->clip_times[i] = ClipTime(c, time, &step);
    offsets_[i] = offset;
    copy_from_[i] = kSampled;
    if (options_.share_quantum > 0) {
      const ShareEntry* shared = FindOrInsertShared(c.clip, step, offset);
      if (shared->offset != offset) copy_from_[i] = shared->offset;
    }
    if (copy_from_[i] == kSampled) order_.push_back(static_cast<uint32_t>(i));
    offset += clips_[c.clip].layout.EncodedSize();
  }
  std::sort(order_.begin(), order_.end(), [&](uint32_t a, uint32_t b) {
    return out->clips[a] != out->clips[b] ? out->clips[a] < out->clips[b] : out->clip_times[a] < out->clip_times[b];
  });
  for (uint32_t i : order_) {
    ClipEntry& entry = clips_[out->clips[i]];
    const size_t joints = entry.layout.joints;
    const FloatPose pose{{scratch_.data(), 4 * joints},
                         {scratch_.data() + 4 * joints, 3 * joints},
                         {scratch_.data() + 7 * joints, 3 * joints}};
    ARMATURE_RETURN_IF_ERROR(
        (ClipSamplingFloatJob{entry.clip.get(), out->clip_times[i], WrapMode::kLoop, &entry.context, pose}.Run()));
    EncodePose(entry.layout, pose, out->poses.data() + offsets_[i]);
    ++samples;
  }
  for (size_t i = 0; i < count; ++i)
    if (copy_from_[i] < kWritten)
      std::memcpy(out->poses.data() + offsets_[i], out->poses.data() + copy_from_[i],
                  clips_[out->clips[i]].layout.EncodedSize());
  out->poses.resize(offset);
  out->samples = samples;
  out->work_us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
  if (count > 0) cost_us_ = 0.8 * cost_us_ + 0.2 * (out->work_us / static_cast<double>(count));
  return Status::Ok();
}

}  // namespace armature
