// `armature crowd`: a CrowdSession from the command line. Adds --characters
// characters on CLIP (spread time offsets, falling significance), runs the
// session for --seconds and prints a line per frame, then the mean tick
// interval, late ticks, deferred characters and bytes per joint.
#include <cstdio>
#include <memory>
#include <string>

#include "armature/crowd_decoder.h"
#include "armature/v1/crowd.grpc.pb.h"
#include "cli_context.h"
#include "cli_messages.h"

namespace armature::cli {
namespace {

struct CrowdFlags {
  std::string skeleton, clip;
  int characters = 100;
  double fps = 30, seconds = 3, budget_ms = 0;
};

struct CrowdSummary {
  uint64_t frames = 0, late = 0, deferred = 0, updated = 0, joint_poses = 0, pose_bytes = 0, wire_bytes = 0;
  double first_wall = 0, last_wall = 0;
};

void Count(const v1::CrowdFrame& frame, const client::CrowdPoses& poses, CrowdSummary& s) {
  if (s.frames == 0) s.first_wall = frame.wall_time();
  s.last_wall = frame.wall_time();
  ++s.frames;
  s.late += frame.stats().late() ? 1 : 0;
  s.deferred += frame.stats().deferred();
  s.updated += frame.stats().updated();
  s.joint_poses += poses.ids.size() * poses.joints;
  s.pose_bytes += frame.poses().size();
  s.wire_bytes += frame.ByteSizeLong() - (frame.new_layouts_size() ? frame.new_layouts(0).ByteSizeLong() : 0);
}

void PrintSummary(const CliContext& ctx, const CrowdSummary& s) {
  const double interval = s.frames > 1 ? (s.last_wall - s.first_wall) / static_cast<double>(s.frames - 1) : 0;
  const double joints = static_cast<double>(std::max<uint64_t>(1, s.joint_poses));
  const nlohmann::json summary = {{"frames", s.frames},
                                  {"meanTickIntervalMs", interval * 1000},
                                  {"lateTicks", s.late},
                                  {"deferredCharacters", s.deferred},
                                  {"meanDeferredPerTick", s.frames ? double(s.deferred) / double(s.frames) : 0.0},
                                  {"updated", s.updated},
                                  {"poseBytesPerJoint", double(s.pose_bytes) / joints},
                                  {"wireBytesPerJoint", double(s.wire_bytes) / joints}};
  if (ctx.json) return PrintJson({{"summary", summary}}, false);
  std::printf(
      "%llu frames, mean tick interval %.3f ms, %llu late ticks, %llu deferred characters (%.1f a tick), "
      "%.3f pose bytes a joint (%.3f on the wire)\n",
      static_cast<unsigned long long>(s.frames), interval * 1000, static_cast<unsigned long long>(s.late),
      static_cast<unsigned long long>(s.deferred), summary["meanDeferredPerTick"].get<double>(),
      summary["poseBytesPerJoint"].get<double>(), summary["wireBytesPerJoint"].get<double>());
}

int Crowd(CliContext& ctx, const CrowdFlags& f) {
  client::Client client = ctx.MakeClient();
  auto stub = v1::CrowdService::NewStub(client.channel());
  grpc::ClientContext context;
  client.Prepare(context, true);  // credentials; the session ends at its --seconds
  auto stream = stub->CrowdSession(&context);
  v1::CrowdCommand start;
  start.mutable_start()->set_fps(f.fps);
  start.mutable_start()->set_duration(f.seconds);
  start.mutable_start()->set_budget_ms(f.budget_ms);
  bool open = stream->Write(start);
  for (int i = 0; open && i < f.characters; ++i) {
    v1::CrowdCommand add;
    v1::CrowdCharacter* c = add.mutable_add();
    c->set_id(static_cast<uint32_t>(i));
    c->set_skeleton(f.skeleton);
    c->set_clip(f.clip);
    c->set_time_offset(0.37 * i);
    c->set_significance(f.characters - i);
    open = stream->Write(add);
  }
  if (open) stream->WritesDone();
  client::CrowdDecoder decoder;
  CrowdSummary summary;
  v1::CrowdFrame frame;
  while (stream->Read(&frame)) {
    const client::CrowdPoses poses = decoder.Decode(frame);
    Count(frame, poses, summary);
    for (const v1::CrowdError& e : frame.errors()) std::fprintf(stderr, "refused: %s\n", e.error().c_str());
    if (ctx.json) {
      PrintJson({{"tick", frame.tick()},
                 {"time", frame.time()},
                 {"wallTime", frame.wall_time()},
                 {"updated", frame.stats().updated()},
                 {"deferred", frame.stats().deferred()},
                 {"late", frame.stats().late()},
                 {"workMs", frame.stats().work_ms()},
                 {"bytes", frame.ByteSizeLong()}},
                false);
    } else {
      std::printf("tick %llu time %.4f updated %u deferred %u%s work %.3f ms %zu bytes\n",
                  static_cast<unsigned long long>(frame.tick()), frame.time(), frame.stats().updated(),
                  frame.stats().deferred(), frame.stats().late() ? " LATE" : "", frame.stats().work_ms(),
                  frame.ByteSizeLong());
    }
  }
  const grpc::Status status = stream->Finish();
  if (!status.ok()) throw client::ClientError(status);
  PrintSummary(ctx, summary);
  std::fflush(stdout);
  return 0;
}

}  // namespace

void AddCrowdCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd = app.add_subcommand("crowd", "Run a crowd of characters on one clip (CrowdSession) and print its ticks");
  auto f = std::make_shared<CrowdFlags>();
  cmd->add_option("SKELETON", f->skeleton, "The characters' skeleton")->required();
  cmd->add_option("CLIP", f->clip, "The clip every character plays (looped, offsets spread)")->required();
  cmd->add_option("--characters", f->characters, "Characters")->capture_default_str()->check(PositiveNumber());
  cmd->add_option("--fps", f->fps, "Ticks per second")->capture_default_str()->check(PositiveNumber());
  cmd->add_option("--seconds", f->seconds, "Session seconds")->capture_default_str()->check(PositiveNumber());
  cmd->add_option("--budget-ms", f->budget_ms, "A tick's work budget (0: the server's --crowd-budget-ms)")
      ->capture_default_str();
  cmd->callback([&ctx, f] { ctx.run = [&ctx, f] { return Crowd(ctx, *f); }; });
}

}  // namespace armature::cli
