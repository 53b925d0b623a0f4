// `armature play`: a PlaybackSession from the command line. Plays a clip,
// optionally crossfades to another from session time --at (sent at once with
// `at`: the server applies it at that frame exactly), and prints one line per
// frame (the playing motions and their weights).
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "armature/v1/poses.grpc.pb.h"
#include "cli_context.h"
#include "cli_messages.h"
#include "files/pose_output.h"

namespace armature::cli {
namespace {

struct PlayFlags {
  std::string skeleton, clip, then;
  double at = 1, crossfade = 0.5, fps = 30, duration = 3;
  std::string space = "local";
  std::vector<std::string> joints;
};

nlohmann::json MotionsJson(const v1::PlaybackFrame& frame) {
  nlohmann::json motions = nlohmann::json::array();
  for (const auto& m : frame.motions())
    motions.push_back({{"id", m.id()}, {"name", m.name()}, {"weight", m.weight()}, {"time", m.time()}});
  return motions;
}

int Play(CliContext& ctx, const PlayFlags& f) {
  client::Client client = ctx.MakeClient();
  auto stub = v1::PoseService::NewStub(client.channel());
  grpc::ClientContext context;
  client.Prepare(context, true);  // credentials; the session ends at its --duration
  auto stream = stub->PlaybackSession(&context);
  v1::PlaybackCommand start;
  v1::PlaybackStart* s = start.mutable_start();
  s->set_skeleton(f.skeleton);
  s->set_fps(f.fps);
  s->set_duration(f.duration);
  s->set_space(f.space == "world" ? v1::WORLD : v1::LOCAL);
  for (const auto& j : f.joints) s->add_joints(j);
  s->mutable_play()->set_clip(f.clip);
  bool open = stream->Write(start);
  if (open && !f.then.empty()) {
    v1::PlaybackCommand play;
    play.mutable_play()->set_clip(f.then);
    play.mutable_play()->set_crossfade(f.crossfade);
    play.set_at(f.at);
    open = stream->Write(play);
  }
  if (open) stream->WritesDone();
  v1::Skeleton skeleton;
  google::protobuf::RepeatedField<int32_t> joints;
  v1::PlaybackFrame frame;
  while (stream->Read(&frame)) {
    if (frame.index() == 0) {
      joints = frame.joints();
      skeleton = client.GetSkeleton(frame.skeleton());
    }
    if (ctx.json) {
      PrintJson({{"index", frame.index()},
                 {"time", frame.time()},
                 {"wallTime", frame.wall_time()},
                 {"motions", MotionsJson(frame)},
                 {"joints", PoseJointsJson(skeleton, joints, frame.pose())}},
                false);
    } else {
      std::printf("frame %llu time %.4f", static_cast<unsigned long long>(frame.index()), frame.time());
      for (const auto& m : frame.motions()) std::printf(" | %s w %.3f t %.4f", m.name().c_str(), m.weight(), m.time());
      std::printf("\n");
    }
    std::fflush(stdout);
  }
  const grpc::Status status = stream->Finish();
  if (!status.ok()) throw client::ClientError(status);
  return 0;
}

}  // namespace

void AddPlayCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd = app.add_subcommand("play", "Play a clip live (PlaybackSession), optionally crossfading to another");
  auto f = std::make_shared<PlayFlags>();
  cmd->add_option("SKELETON", f->skeleton, "The session's skeleton")->required();
  cmd->add_option("CLIP", f->clip, "The clip played from the first frame")->required();
  cmd->add_option("--then", f->then, "A clip to crossfade to");
  cmd->add_option("--at", f->at, "Session time (s) from which --then plays")->capture_default_str();
  cmd->add_option("--crossfade", f->crossfade, "Crossfade seconds for --then")->capture_default_str();
  cmd->add_option("--fps", f->fps, "Frames per second")->capture_default_str()->check(PositiveNumber());
  cmd->add_option("--duration", f->duration, "Session seconds")->capture_default_str()->check(PositiveNumber());
  cmd->add_option("--space", f->space, "local or world")->capture_default_str()->transform(OneOf({"local", "world"}));
  cmd->add_option("--joints", f->joints, "Only these joints")->delimiter(',');
  cmd->callback([&ctx, f] { ctx.run = [&ctx, f] { return Play(ctx, *f); }; });
}

}  // namespace armature::cli
