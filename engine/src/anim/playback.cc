// Playback: crossfades, pause, seek and layer control over bound motions.
#include "armature/engine/anim/playback.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace armature {
namespace {

// A fade within this of its end counts as complete (the frame clock adds
// 1/fps repeatedly, which may land a rounding short of the end).
constexpr double kFadeEpsilon = 1e-9;

}  // namespace

double Playback::Entry::Weight() const {
  if (fade_duration <= 0 || fade_elapsed >= fade_duration - kFadeEpsilon) return weight_to;
  return weight_from + (weight_to - weight_from) * (fade_elapsed / fade_duration);
}

bool Playback::Entry::FadedOut() const {
  return weight_to == 0 && (fade_duration <= 0 || fade_elapsed >= fade_duration - kFadeEpsilon);
}

Playback::Playback(std::shared_ptr<const Skeleton> skeleton) : skeleton_(std::move(skeleton)) {}

Status Playback::Play(const Motion& motion, double crossfade, uint64_t id) {
  if (!std::isfinite(crossfade) || crossfade < 0)
    return Status::InvalidArgument("crossfade: " + std::to_string(crossfade) + " is not a finite time >= 0");
  ARMATURE_ASSIGN_OR_RETURN(auto plan, BindMotion(motion));
  const Skeleton& sk = *plan.skeleton;
  if (sk.names != skeleton_->names) {
    size_t j = 0;
    while (j < sk.size() && j < skeleton_->size() && sk.names[j] == skeleton_->names[j]) ++j;
    return Status::InvalidArgument("layers[0] (clip '" +
                                   (motion.layers.empty() ? std::string() : motion.layers[0].clip_name) +
                                   "'): its skeleton is not the session's: joint " + std::to_string(j) + " is '" +
                                   (j < sk.size() ? sk.names[j] : std::string("(none)")) + "', the session's is '" +
                                   (j < skeleton_->size() ? skeleton_->names[j] : std::string("(none)")) + "'");
  }
  std::vector<Entry> before = motions_;
  if (crossfade == 0) motions_.clear();
  for (Entry& m : motions_) {  // each fades out from where it is now
    m.weight_from = m.Weight();
    m.weight_to = 0;
    m.fade_elapsed = 0;
    m.fade_duration = crossfade;
  }
  Entry next;
  next.id = id;
  next.motion = motion;
  next.plan = std::move(plan);
  next.weight_from = crossfade == 0 ? 1 : 0;
  next.fade_duration = crossfade;
  motions_.push_back(std::move(next));
  if (motions_.size() > kMaxMotions) motions_.erase(motions_.begin());
  if (Status st = Rebind(); !st.ok()) {
    motions_ = std::move(before);
    (void)Rebind();
    return st;
  }
  return Status::Ok();
}

Status Playback::CheckLayer(size_t layer) const {
  if (motions_.empty()) return Status::InvalidArgument("layer: nothing is playing");
  const size_t n = motions_.back().motion.layers.size();
  if (layer >= n)
    return Status::InvalidArgument("layer: " + std::to_string(layer) + " is out of range (the motion playing has " +
                                   std::to_string(n) + (n == 1 ? " layer)" : " layers)"));
  return Status::Ok();
}

Status Playback::SetLayerWeight(size_t layer, double weight) {
  ARMATURE_RETURN_IF_ERROR(CheckLayer(layer));
  if (!std::isfinite(weight) || weight < 0 || weight > 1)
    return Status::InvalidArgument("weight: " + std::to_string(weight) + " of layer " + std::to_string(layer) +
                                   " is outside [0, 1]");
  motions_.back().motion.layers[layer].weight = weight;
  Refresh();
  return Status::Ok();
}

Status Playback::SetLayerSpeed(size_t layer, double speed) {
  ARMATURE_RETURN_IF_ERROR(CheckLayer(layer));
  if (!std::isfinite(speed))
    return Status::InvalidArgument("speed: of layer " + std::to_string(layer) + " is not finite");
  Entry& m = motions_.back();
  BoundLayer& b = m.plan.layers[layer];
  // time·speed + offset stays where it is at the current time.
  b.time_offset += m.time * (b.speed - speed);
  b.speed = speed;
  m.motion.layers[layer].speed = speed;
  m.motion.layers[layer].time_offset = b.time_offset;
  Refresh();
  return Status::Ok();
}

Status Playback::Seek(double time) {
  if (!std::isfinite(time) || time < 0)
    return Status::InvalidArgument("time: " + std::to_string(time) + " is not a finite time >= 0");
  if (motions_.empty()) return Status::InvalidArgument("time: nothing is playing");
  motions_.back().time = time;
  Refresh();
  return Status::Ok();
}

void Playback::Advance(double dt) {
  if (paused_ || !(dt > 0) || !std::isfinite(dt)) return;
  for (Entry& m : motions_) {
    m.time += dt;
    m.fade_elapsed += dt;
  }
  const size_t before = motions_.size();
  std::erase_if(motions_, [](const Entry& m) { return m.FadedOut(); });
  if (motions_.size() != before) {
    (void)Rebind();  // a subset of a blend that bound: binds again
    return;
  }
  Refresh();
}

Status Playback::Rebind() {
  blend_ = MotionPlan();
  mask_weights_.clear();
  source_.clear();
  if (motions_.empty()) return Status::Ok();
  Motion all = Describe();
  for (MotionLayer& l : all.layers) l.weight = 1, l.time_offset = 0;
  ARMATURE_ASSIGN_OR_RETURN(auto plan, BindMotion(all));
  blend_ = std::move(plan);
  for (size_t e = 0; e < motions_.size(); ++e)
    for (size_t i = 0; i < motions_[e].motion.layers.size(); ++i) source_.emplace_back(e, i);
  for (const BoundLayer& l : blend_.layers) mask_weights_.push_back(l.joint_weight);
  Refresh();
  return Status::Ok();
}

void Playback::Refresh() {
  for (size_t k = 0; k < source_.size() && k < blend_.layers.size(); ++k) {
    const auto [e, i] = source_[k];
    const Entry& m = motions_[e];
    const double w = m.motion.layers[i].weight * m.Weight();
    BoundLayer& b = blend_.layers[k];
    b.weight = w;
    for (size_t j = 0; j < b.joint_weight.size(); ++j) b.joint_weight[j] = mask_weights_[k][j] * w;
    // The layer's clip time, unwrapped (completed loops kept for ACCUMULATE),
    // as an offset at blend time 0.
    const BoundLayer& src = m.plan.layers[i];
    b.speed = 1;
    if (m.plan.sync == TimeSync::kNone) {
      b.time_offset = m.time * src.speed + src.time_offset;
    } else {
      const LayerTime lt = LayerTimeAt(m.plan, i, m.time);
      b.time_offset = lt.time + static_cast<double>(lt.loops) * src.clip->duration;
    }
  }
}

Status Playback::Evaluate(MotionWorkspace& workspace, std::span<Trs> output, RootDelta* root_delta) const {
  if (output.size() != skeleton_->size())
    return Status::InvalidArgument("playback: output has room for " + std::to_string(output.size()) +
                                   " transforms, the skeleton has " + std::to_string(skeleton_->size()) + " joints");
  if (motions_.empty()) {
    std::copy(skeleton_->rest.begin(), skeleton_->rest.end(), output.begin());
    if (root_delta) *root_delta = RootDelta();
    return Status::Ok();
  }
  workspace.Resize(blend_);  // no allocation when it fits (the same layers and clips)
  const BlendMotionJob job{&blend_, 0.0, &workspace, output, root_delta};
  return job.Run();
}

Motion Playback::Describe() const {
  Motion d;
  if (motions_.empty()) return d;
  const Entry& newest = motions_.back();
  d.sync = TimeSync::kNone;
  d.root_motion = newest.motion.root_motion;
  d.up = newest.motion.up;
  if (newest.plan.root >= 0) d.root_joint = newest.plan.skeleton->names[newest.plan.root];
  size_t k = 0;
  for (const Entry& m : motions_)
    for (const MotionLayer& layer : m.motion.layers) {
      MotionLayer l = layer;
      l.speed = 1;
      if (k < blend_.layers.size()) {
        l.weight = blend_.layers[k].weight;
        l.time_offset = blend_.layers[k].time_offset;
      }
      d.layers.push_back(std::move(l));
      ++k;
    }
  return d;
}

PlayingMotion Playback::playing(size_t i) const {
  const Entry& m = motions_.at(i);
  return {m.id, m.Weight(), m.time};
}

}  // namespace armature
