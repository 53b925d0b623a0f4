#include "server/pose/playback_commands.h"

#include <cmath>

#include "server/assets/motion_convert.h"
#include "server/rpc/request_validation.h"
#include "server/rpc/work/work_budget.h"

namespace armature::server {
namespace {

// What `play` names as a motion, and the name frames show for it.
Status PlayedMotion(const Catalog& catalog, const Limits& limits, const v1::PlaybackPlay& play,
                    const std::string& field, Motion& motion, std::string& name) {
  if (play.has_motion()) {
    auto m = MotionFromProto(catalog, play.motion(), limits, field + ".motion");
    if (!m.ok()) return m.status();
    motion = std::move(*m);
    name.clear();
    for (const MotionLayer& l : motion.layers) name += (name.empty() ? "" : "+") + l.clip_name;
    return Status::Ok();
  }
  if (play.clip().empty()) return Status::InvalidArgument(field + ": give a clip or a motion to play");
  auto ref = catalog.FindClip(play.clip());
  if (!ref.ok()) return ref.status().WithContext(field + ".clip: ");
  motion = Motion();
  MotionLayer layer;
  layer.clip = ref->part->runtime;
  layer.clip_name = ref->part->name;
  motion.layers.push_back(std::move(layer));  // weight 1, looping
  name = ref->part->name;
  return Status::Ok();
}

Status Play(const Catalog& catalog, const Limits& limits, const v1::PlaybackPlay& play, const std::string& field,
            uint64_t id, Playback& playback, std::map<uint64_t, std::string>& names) {
  Motion motion;
  std::string name;
  ARMATURE_RETURN_IF_ERROR(PlayedMotion(catalog, limits, play, field, motion, name));
  ARMATURE_RETURN_IF_ERROR(ValidateFinite(play.crossfade(), field + ".crossfade"));
  if (Status st = playback.Play(motion, play.crossfade(), id); !st.ok())
    return st.WithContext(field + (play.has_motion() ? ".motion." : "."));
  // Keep the names of the motions still playing (bounded by Playback::kMaxMotions).
  for (auto it = names.begin(); it != names.end();) {
    bool playing = false;
    for (size_t i = 0; i < playback.playing_count(); ++i) playing |= playback.playing(i).id == it->first;
    it = playing ? std::next(it) : names.erase(it);
  }
  names[id] = std::move(name);
  return Status::Ok();
}

}  // namespace

StatusOr<PlaybackSetup> StartPlayback(const Catalog& catalog, const Limits& limits, const v1::PlaybackStart& start,
                                      std::unique_ptr<Playback>& playback, std::map<uint64_t, std::string>& names) {
  ARMATURE_RETURN_IF_ERROR(ValidateRequired(start.skeleton(), "start.skeleton"));
  auto skeleton = catalog.FindSkeleton(start.skeleton());
  if (!skeleton.ok()) return skeleton.status().WithContext("start.skeleton: ");
  StreamPacing pacing{start.fps(), 1, true, 0, start.duration()};
  if (Status st = ValidatePacing(pacing, limits); !st.ok()) return st.WithContext("start.");
  if (Status st = ValidateEnum(start.space(), v1::Space_descriptor(), "start.space"); !st.ok()) return st;
  auto joints = ResolveJoints(*skeleton->part->skeleton, start.joints(), "start.joints");
  if (!joints.ok()) return joints.status();
  PlaybackSetup setup;
  setup.skeleton = std::move(*skeleton);
  setup.fps = pacing.fps;
  setup.duration = pacing.duration;
  setup.space = start.space() == v1::WORLD ? v1::WORLD : v1::LOCAL;
  setup.joints = std::move(*joints);
  playback = std::make_unique<Playback>(setup.skeleton.part->skeleton);
  names.clear();
  if (start.has_play()) {
    ARMATURE_RETURN_IF_ERROR(Play(catalog, limits, start.play(), "start.play", 0, *playback, names));
    ARMATURE_RETURN_IF_ERROR(ValidatePlaybackWork(setup, *playback, limits, "start.play"));
  }
  return setup;
}

Status ApplyPlaybackCommand(const Catalog& catalog, const Limits& limits, const v1::PlaybackCommand& command,
                            uint64_t id, Playback& playback, std::map<uint64_t, std::string>& names) {
  switch (command.command_case()) {
    case v1::PlaybackCommand::kStart: return Status::InvalidArgument("start: only in the first message");
    case v1::PlaybackCommand::kPlay: return Play(catalog, limits, command.play(), "play", id, playback, names);
    case v1::PlaybackCommand::kSetLayer: {
      const v1::PlaybackSetLayer& s = command.set_layer();
      if (!s.has_weight() && !s.has_speed())
        return Status::InvalidArgument("set_layer: give a weight, a speed or both");
      if (s.layer() < 0)
        return Status::InvalidArgument("set_layer.layer: " + std::to_string(s.layer()) + " is negative");
      const size_t layer = static_cast<size_t>(s.layer());
      // Both checked before either applies: a bad command changes nothing.
      if (s.has_weight() && (!std::isfinite(s.weight()) || s.weight() < 0 || s.weight() > 1))
        return Status::InvalidArgument("set_layer.weight: " + std::to_string(s.weight()) + " is outside [0, 1]");
      if (s.has_speed()) ARMATURE_RETURN_IF_ERROR(ValidateFinite(s.speed(), "set_layer.speed"));
      if (s.has_weight())
        ARMATURE_RETURN_IF_ERROR(playback.SetLayerWeight(layer, s.weight()).WithContext("set_layer."));
      if (s.has_speed()) ARMATURE_RETURN_IF_ERROR(playback.SetLayerSpeed(layer, s.speed()).WithContext("set_layer."));
      return Status::Ok();
    }
    case v1::PlaybackCommand::kPause: playback.Pause(); return Status::Ok();
    case v1::PlaybackCommand::kResume: playback.Resume(); return Status::Ok();
    case v1::PlaybackCommand::kSeek: return playback.Seek(command.seek().time()).WithContext("seek.");
    case v1::PlaybackCommand::COMMAND_NOT_SET: break;
  }
  return Status::InvalidArgument("command: empty (give one of play, set_layer, pause, resume, seek)");
}

Status ValidatePlaybackWork(const PlaybackSetup& setup, const Playback& playback, const Limits& limits,
                            const std::string& field) {
  return ValidateStreamWork(static_cast<int64_t>(playback.layer_count()),
                            static_cast<int64_t>(setup.skeleton.part->skeleton->size()), setup.fps, limits,
                            field + " (" + std::to_string(playback.playing_count()) +
                                (playback.playing_count() == 1 ? " motion" : " motions") + " playing)");
}

Status FillPlaybackFrame(const PlaybackSetup& setup, const Playback& playback,
                         const std::map<uint64_t, std::string>& names, uint64_t index, MotionWorkspace& motion_ws,
                         PoseWorkspace& pose_ws, v1::PlaybackFrame& frame) {
  const Skeleton& skeleton = *setup.skeleton.part->skeleton;
  frame.set_index(index);
  frame.set_time(static_cast<double>(index) / setup.fps);
  frame.set_paused(playback.paused());
  for (size_t i = 0; i < playback.playing_count(); ++i) {
    const PlayingMotion m = playback.playing(i);
    v1::PlaybackMotion* out = frame.add_motions();
    out->set_id(m.id);
    if (auto it = names.find(m.id); it != names.end()) out->set_name(it->second);
    out->set_weight(m.weight);
    out->set_time(m.time);
  }
  pose_ws.Resize(skeleton.size());
  const bool extract = playback.playing_count() > 0 && playback.root_motion() == RootMotion::kExtract;
  RootDelta delta;
  ARMATURE_RETURN_IF_ERROR(playback.Evaluate(motion_ws, pose_ws.local, extract ? &delta : nullptr));
  PackPose(skeleton, setup.space, setup.joints, pose_ws, frame.mutable_pose());
  if (extract) {
    v1::Pose* root = frame.mutable_root_motion();
    for (double v : delta.translation) root->add_translations(static_cast<float>(v));
    for (double v : {delta.rotation.w(), delta.rotation.x(), delta.rotation.y(), delta.rotation.z()})
      root->add_rotations(static_cast<float>(v));
  }
  if (index == 0) {
    for (int j : setup.joints) frame.add_joints(j);
    frame.set_skeleton(setup.skeleton.part->name);
  }
  return Status::Ok();
}

}  // namespace armature::server
