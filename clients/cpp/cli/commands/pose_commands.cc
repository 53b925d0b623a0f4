// pose and stream.
#include <cstdio>
#include <iostream>
#include <map>

#include "cli_context.h"
#include "cli_messages.h"
#include "files/motion_file.h"
#include "files/pose_output.h"

namespace armature::cli {
namespace {

const std::map<std::string, v1::Space> kSpaces = {{"local", v1::LOCAL}, {"world", v1::WORLD}};
const std::map<std::string, v1::Interpolation> kInterpolations = {
    {"step", v1::STEP}, {"linear", v1::LINEAR}, {"cubic", v1::CUBIC}};

struct PoseFlags {
  std::string clip;
  std::string space = "world";
  std::string interpolation;
  std::vector<std::string> joints;
  std::string motion;  // FILE.json: a motion instead of CLIP
};

// `pose` and `stream` take CLIP or --motion FILE.json.
void AddPoseFlags(CLI::App* cmd, PoseFlags& f) {
  auto* clip = cmd->add_option("CLIP", f.clip, "Clip name");
  cmd->add_option("--motion", f.motion, "A motion (clips in layers) as proto3 JSON, instead of CLIP")
      ->excludes(clip)
      ->check(CLI::ExistingFile);
  cmd->add_option("--space", f.space, "local or world")->capture_default_str()->transform(OneOf({"local", "world"}));
  cmd->add_option("--interpolation", f.interpolation, "step, linear or cubic (default: the clip's own)")
      ->transform(OneOf({"step", "linear", "cubic"}));
  cmd->add_option("--joints", f.joints, "Only these joints")->delimiter(',');
}

template <class Request>
void FillPoseRequest(const PoseFlags& f, Request& r) {
  r.set_clip(f.clip);
  r.set_space(kSpaces.at(f.space));
  if (!f.interpolation.empty()) r.set_interpolation(kInterpolations.at(f.interpolation));
  for (const auto& j : f.joints) r.add_joints(j);
}

// `pose --motion FILE.json`: the same output as `pose CLIP`, with "motion"
// (the file) and "skeleton" in place of "clip", and EXTRACT's "rootMotion".
int PrintMotionPose(client::Client& client, const PoseFlags& f, double time, bool json) {
  v1::EvaluateMotionRequest request;
  *request.mutable_motion() = ReadMotionFile(f.motion);
  request.add_times(time);
  request.set_space(kSpaces.at(f.space));
  for (const auto& j : f.joints) request.add_joints(j);
  const auto response = client.EvaluateMotion(request);
  const auto skeleton = client.GetSkeleton(response.skeleton());
  if (json) {
    nlohmann::json out = {{"motion", f.motion},
                          {"skeleton", response.skeleton()},
                          {"time", time},
                          {"space", f.space},
                          {"joints", PoseJointsJson(skeleton, response.joints(), response.poses(0))}};
    if (response.root_motion_size() > 0) out["rootMotion"] = RootMotionJson(response.root_motion(0));
    PrintJson(out);
  } else {
    std::printf("motion %s (skeleton %s) at %.6f s (%s space)\n", f.motion.c_str(), response.skeleton().c_str(), time,
                f.space.c_str());
    PrintPoseTable(skeleton, response.joints(), response.poses(0));
  }
  return 0;
}

}  // namespace

void AddPoseCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd = app.add_subcommand("pose", "Evaluate a clip at a time");
  auto flags = std::make_shared<PoseFlags>();
  auto time = std::make_shared<double>(0);
  auto loop = std::make_shared<bool>(false);
  AddPoseFlags(cmd, *flags);
  cmd->add_option("--time,-t", *time, "Clip (or motion) time in seconds")->required();
  cmd->add_flag("--loop", *loop, "Wrap times past the end (default: clamp; motion layers loop unless told)");
  cmd->callback([&ctx, cmd, flags, time, loop] {
    if (cmd->count("CLIP") + cmd->count("--motion") == 0) throw CLI::RequiredError("CLIP or --motion");
    ctx.run = [&ctx, flags, time, loop] {
      client::Client client = ctx.MakeClient();
      if (!flags->motion.empty()) return PrintMotionPose(client, *flags, *time, ctx.json);
      v1::EvaluateClipRequest request;
      FillPoseRequest(*flags, request);
      request.add_times(*time);
      request.set_wrap(*loop ? v1::LOOP : v1::CLAMP);
      const auto response = client.EvaluateClip(request);
      const auto skeleton = client.GetSkeleton(response.skeleton());
      if (ctx.json) {
        PrintJson({{"clip", response.clip()},
                   {"time", *time},
                   {"space", flags->space},
                   {"joints", PoseJointsJson(skeleton, response.joints(), response.poses(0))}});
      } else {
        std::printf("clip %s at %.6f s (%s space)\n", response.clip().c_str(), *time, flags->space.c_str());
        PrintPoseTable(skeleton, response.joints(), response.poses(0));
      }
      return 0;
    };
  });
}

void AddStreamCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd = app.add_subcommand("stream", "Play a clip or a motion: one line per frame, paced in real time");
  auto flags = std::make_shared<PoseFlags>();
  auto fps = std::make_shared<double>(30);
  auto duration = std::make_shared<double>(0);
  auto speed = std::make_shared<double>(1);
  auto loop = std::make_shared<bool>(false);
  AddPoseFlags(cmd, *flags);
  cmd->add_option("--fps", *fps, "Frames per second")->capture_default_str()->check(PositiveNumber());
  cmd->add_option("--duration", *duration, "Stop after this many seconds (default: at the clip's end)");
  cmd->add_option("--speed", *speed, "Playback speed")->capture_default_str();
  cmd->add_flag("--loop", *loop, "Loop the clip (a motion: keep playing past its first layer's end)");
  cmd->callback([&ctx, cmd, flags, fps, duration, speed, loop] {
    if (cmd->count("CLIP") + cmd->count("--motion") == 0) throw CLI::RequiredError("CLIP or --motion");
    ctx.run = [&ctx, flags, fps, duration, speed, loop] {
      client::Client client = ctx.MakeClient();
      v1::StreamClipRequest r;
      FillPoseRequest(*flags, r);
      if (!flags->motion.empty()) *r.mutable_motion() = ReadMotionFile(flags->motion);
      r.set_fps(*fps);
      r.set_duration(*duration);
      r.set_speed(*speed);
      r.set_loop(*loop);
      v1::Skeleton skeleton;
      google::protobuf::RepeatedField<int32_t> joints;
      client.StreamClip(r, [&](const v1::PoseFrame& frame) {
        if (frame.index() == 0) {
          joints = frame.joints();
          skeleton = client.GetSkeleton(frame.skeleton());
        }
        if (ctx.json) {
          nlohmann::json out = {{"index", frame.index()},
                                {"time", frame.time()},
                                {"wallTime", frame.wall_time()},
                                {"joints", PoseJointsJson(skeleton, joints, frame.pose())}};
          // A motion with rootMotion EXTRACT: the root's motion since the previous frame.
          if (frame.has_root_delta()) out["rootDelta"] = RootMotionJson(frame.root_delta());
          PrintJson(out, false);
        } else {
          // The first joint (the root, unless --joints says otherwise) stands for the frame.
          const auto& t = frame.pose().translations();
          std::printf("frame %llu time %.4f wall %.4f %s (%.4f, %.4f, %.4f)\n",
                      static_cast<unsigned long long>(frame.index()), frame.time(), frame.wall_time(),
                      joints.empty() ? "" : skeleton.joints(joints[0]).name().c_str(), t.size() > 0 ? t[0] : 0.f,
                      t.size() > 1 ? t[1] : 0.f, t.size() > 2 ? t[2] : 0.f);
        }
        std::fflush(stdout);
        return true;
      });
      return 0;
    };
  });
}

}  // namespace armature::cli
