// A crowd's characters ticked under a budget (issue 31): each tick picks the
// characters due (crowd_schedule.h), samples their clips with
// ClipSamplingJob at their clip time (looped) and encodes each local pose
// (pose_encoding.h) into one buffer. Characters on the same clip at the same
// quantized clip time share one sample and its bytes. The per-update cost is
// measured (or fixed, for tests) and sets the next tick's capacity.
// Steady ticks allocate nothing: the buffers grow when characters are added.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "armature/base/status.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/anim/crowd/crowd_motion.h"
#include "armature/engine/anim/crowd/pose_encoding.h"
#include "armature/engine/anim/motion.h"

namespace armature {

struct CrowdTickOptions {
  double budget_us = 1000;    // a tick's work budget
  uint32_t max_interval = 8;  // the longest a character waits between updates, in ticks (1–255)
  double share_quantum = 0;   // seconds; > 0: clip times rounded to it, equal ones share a sample
  double fixed_cost_us = 0;   // > 0: the cost of one update, instead of the measured one
};

struct CrowdCharacter {
  uint32_t id = 0;
  uint32_t clip = 0;  // from CrowdTicker::AddClip or AddMotion
  double time_offset = 0;
  double speed = 1;
  double significance = 0;  // higher is updated more often (e.g. 1 / distance to the camera)
};

// One tick's output: the characters updated, in significance order, their
// clip times, and their encoded poses one after another.
struct CrowdTick {
  uint64_t tick = 0;
  double time = 0;
  std::vector<uint32_t> ids;
  std::vector<uint32_t> clips;     // per id: its clip (or motion)
  std::vector<double> clip_times;  // per id: the clip time sampled (a motion's: its motion time)
  std::vector<uint8_t> poses;
  size_t deferred = 0;  // characters not updated this tick
  size_t reduced = 0;   // characters with an interval over one tick
  size_t samples = 0;   // clip samples taken (updates minus those shared)
  double work_us = 0;   // measured time of this tick's sampling and encoding
  double cost_us = 0;   // the per-update cost the schedule assumed
};

class CrowdTicker {
 public:
  explicit CrowdTicker(CrowdTickOptions options);

  // A clip the characters may play; the same pointer twice is one clip.
  StatusOr<uint32_t> AddClip(std::shared_ptr<const CompressedClip> clip);
  // A bound motion the characters may play, in the clips' numbering (its
  // layout is LayoutOfMotion's); the same plan twice is one motion. Motion
  // characters share blends per (motion, quantized motion time), as clips do.
  StatusOr<uint32_t> AddMotion(std::shared_ptr<const MotionPlan> plan);
  const PoseLayout& layout(uint32_t clip) const { return clips_[clip].layout; }
  const CompressedClip& clip(uint32_t clip) const { return *clips_[clip].clip; }  // a clip's, not a motion's

  // INVALID_ARGUMENT naming the character for a duplicate (Add) or unknown
  // (Update, Remove) id, an unknown clip, non-finite numbers.
  Status Add(const CrowdCharacter& character);
  Status Update(const CrowdCharacter& character);
  Status Remove(uint32_t id);
  bool Has(uint32_t id) const { return slot_of_.count(id) != 0; }
  size_t size() const { return characters_.size(); }

  // Tick `tick` at session time `time`.
  Status Tick(uint64_t tick, double time, CrowdTick* out);

 private:
  struct ClipEntry {
    std::shared_ptr<const CompressedClip> clip;
    PoseLayout layout;
    // The segment last sampled: characters due one after the other often
    // play the same segment, whose header is then read once.
    ClipSamplingContext context;
    std::unique_ptr<CrowdMotion> motion;  // set for a motion (then `clip` is null)
  };
  struct ShareEntry {  // one sample of a tick: (clip, quantized step) → its bytes in the output
    uint64_t generation = 0;
    uint32_t clip = 0;
    int64_t step = 0;
    size_t offset = 0;
  };
  Status Check(const CrowdCharacter& character) const;
  void Grow();
  // A motion character's update: its motion at offset + speed·time (rounded when sharing), encoded at
  // *offset; a blend taken counts in *samples.
  Status TickMotion(const CrowdCharacter& c, double time, size_t index, CrowdTick* out, size_t* offset,
                    size_t* samples);
  double ClipTime(const CrowdCharacter& c, double time, int64_t* step) const;
  // The output offset of this (clip, step)'s pose when already encoded this tick, else inserts `offset`.
  const ShareEntry* FindOrInsertShared(uint32_t clip, int64_t step, size_t offset);

  CrowdTickOptions options_;
  std::vector<ClipEntry> clips_;
  std::vector<CrowdCharacter> characters_;  // by slot
  std::vector<uint8_t> intervals_;
  std::vector<int64_t> last_tick_;
  std::unordered_map<uint32_t, uint32_t> slot_of_;  // id → slot
  std::vector<uint32_t> ranked_, due_;
  bool rank_dirty_ = false;
  size_t max_joints_ = 0, max_pose_bytes_ = 0;
  std::vector<size_t> offsets_;      // per due character: its pose's place in the output
  std::vector<size_t> copy_from_;    // per due character: the offset of the pose it shares, or -1: sampled, -2: written
  std::vector<uint32_t> order_;      // the due characters sampled, by clip and clip time: the sampling order
  std::vector<float> scratch_;       // a pose as ClipSamplingFloatJob's lanes (10 floats a joint)
  std::vector<Trs> motion_scratch_;  // a motion's blended pose
  std::vector<ShareEntry> shared_;   // open addressing, a power of two over twice the characters
  uint64_t generation_ = 0;
  double cost_us_ = 1.0;  // measured: a moving average of work per update
};

}  // namespace armature
