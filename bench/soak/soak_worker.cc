#include "soak_worker.h"

#include <map>
#include <sstream>

#include "armature/v1/authoring.grpc.pb.h"

namespace armature::soak {
namespace {
using Clock = std::chrono::steady_clock;

constexpr int kGrid = 8;

// A small BVH for the import/delete churn: one root joint and an End Site,
// turning about Y over `frames` frames.
std::string SmallBvh(int frames) {
  std::ostringstream s;
  s << "HIERARCHY\nROOT Root\n{\n  OFFSET 0 0 0\n"
    << "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
    << "  End Site\n  {\n    OFFSET 0 1 0\n  }\n}\nMOTION\nFrames: " << frames << "\nFrame Time: 0.1\n";
  for (int f = 0; f < frames; ++f) s << "0 0 0 0 0 " << 10 * f << "\n";
  return s.str();
}

void SetDeadline(grpc::ClientContext& context) {
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
}

}  // namespace

const std::vector<std::string>& MixEntries() {
  static const std::vector<std::string> kEntries = {
      "evaluate", "stream", "ik",        "ik_session", "skin",     "deform",     "list",     "import_delete", "motion",
      "bake",     "export", "character", "retarget",   "playback", "ws_session", "grpc_web", "rest_binary"};
  return kEntries;
}

std::string GridObj() {
  std::ostringstream s;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i) s << "v " << i / double(kGrid - 1) << " " << j / double(kGrid - 1) << " 0\n";
  for (int j = 0; j + 1 < kGrid; ++j)
    for (int i = 0; i + 1 < kGrid; ++i) {
      const int a = j * kGrid + i + 1, b = a + 1, c = a + kGrid, d = c + 1;
      s << "f " << a << " " << b << " " << d << "\nf " << a << " " << d << " " << c << "\n";
    }
  return s.str();
}

Worker::Worker(const std::string& target, int http_port, int id, const Mix& mix, Stats& stats)
    : id_(id), mix_(mix), stats_(stats), rng_(1000 + id), http_(http_port), has_http_(http_port > 0) {
  client::ClientOptions o;
  o.target = target;
  o.timeout = std::chrono::seconds(10);
  o.stream_timeout = std::chrono::seconds(10);
  client_ = std::make_unique<client::Client>(o);
}

void Worker::Run(Clock::time_point deadline) {
  while (Clock::now() < deadline) {
    int pick = static_cast<int>(rng_() % mix_.total);
    for (const auto& [name, w] : mix_.weights) {
      if (pick < w) {
        Call(name);
        break;
      }
      pick -= w;
    }
  }
}

void Worker::Timed(const std::string& method, const std::function<void()>& call) {
  TimedStatus(method, [&] {
    call();
    return grpc::Status::OK;
  });
}

void Worker::TimedStatus(const std::string& method, const std::function<grpc::Status()>& call) {
  const auto t0 = Clock::now();
  grpc::Status st = grpc::Status::OK;
  try {
    st = call();
  } catch (const client::ClientError& e) {
    st = grpc::Status(e.code(), e.what());
  } catch (const std::exception& e) {
    st = grpc::Status(grpc::StatusCode::UNKNOWN, e.what());
  }
  stats_.Record(method, std::chrono::duration<double, std::milli>(Clock::now() - t0).count(), st);
}

v1::SolveIkRequest Worker::IkStart() {
  v1::SolveIkRequest r;
  r.set_skeleton("demo_walk");
  auto* e = r.add_effectors();
  e->set_joint("LeftWrist");
  for (double v : {20 + Jitter(4), 30 + Jitter(4), 20 + Jitter(4)}) e->add_target_position(v);
  return r;
}

v1::EvaluateClipRequest Worker::Evaluate() {
  v1::EvaluateClipRequest r;
  r.set_clip("demo_walk");
  for (int k = 0; k < 8; ++k) r.add_times(ClipTime());
  return r;
}

// demo_walk three times: two override layers at other phases, and an additive one.
v1::Motion Worker::ThreeLayers() {
  v1::Motion m;
  for (int k = 0; k < 3; ++k) {
    auto* layer = m.add_layers();
    layer->set_clip("demo_walk");
    layer->set_weight(k == 2 ? 0.3 : 0.5);
    layer->set_time_offset(ClipTime());
    if (k == 2) layer->set_mode(v1::MotionLayer::ADDITIVE);
  }
  return m;
}

void Worker::Call(const std::string& kind) {
  using Member = void (Worker::*)();
  static const std::map<std::string, Member> kCalls = {{"evaluate", &Worker::CallEvaluate},
                                                       {"stream", &Worker::CallStream},
                                                       {"ik_session", &Worker::CallIkSession},
                                                       {"deform", &Worker::CallDeform},
                                                       {"list", &Worker::CallList},
                                                       {"import_delete", &Worker::CallImportDelete},
                                                       {"bake", &Worker::CallBake},
                                                       {"retarget", &Worker::CallRetarget},
                                                       {"playback", &Worker::CallPlayback},
                                                       {"ws_session", &Worker::CallWebSocketSession}};
  if (auto it = kCalls.find(kind); it != kCalls.end()) return (this->*it->second)();
  if (kind == "ik") {
    Timed("SolveIk", [&] { client_->SolveIk(IkStart()); });
  } else if (kind == "skin") {
    v1::SkinMeshRequest r;
    r.set_mesh("demo_character.body");
    r.set_clip("demo_character.walk");
    r.set_time(ClipTime());
    Timed("SkinMesh", [&] { client_->SkinMesh(r); });
  } else if (kind == "motion") {
    v1::EvaluateMotionRequest r;
    *r.mutable_motion() = ThreeLayers();
    for (int k = 0; k < 16; ++k) r.add_times(ClipTime());
    Timed("EvaluateMotion", [&] { client_->EvaluateMotion(r); });
  } else if (kind == "export") {
    Timed("ExportClip", [&] { client_->ExportClip("demo_character.walk", "glb", true); });
  } else if (kind == "character") {
    v1::SkinCharacterRequest r;
    r.set_skeleton("demo_character");
    r.set_clip("demo_character.walk");
    r.set_time(ClipTime());
    v1::SkinCharacterResponse answer;
    TimedStatus("SkinCharacter", [&] {
      grpc::ClientContext context;
      SetDeadline(context);
      return v1::MeshService::NewStub(client_->channel())->SkinCharacter(&context, r, &answer);
    });
  } else if (kind == "grpc_web" && has_http_) {
    v1::EvaluateClipResponse answer;
    TimedStatus("gRPC-Web", [&] { return http_.GrpcWeb("/armature.v1.PoseService/EvaluateClip", Evaluate(), answer); });
  } else if (kind == "rest_binary" && has_http_) {
    v1::EvaluateClipRequest r = Evaluate();
    r.clear_clip();  // the path names it
    v1::EvaluateClipResponse answer;
    TimedStatus("REST binary", [&] { return http_.RestBinary("/v1/clips/demo_walk:evaluate", r, answer); });
  }
}

void Worker::CallEvaluate() {
  Timed("EvaluateClip", [&] { client_->EvaluateClip(Evaluate()); });
}

void Worker::CallStream() {
  v1::StreamClipRequest r;
  r.set_clip("demo_walk");
  r.set_fps(60);
  r.set_duration(0.25);
  Timed("StreamClip", [&] { client_->StreamClip(r, [](const v1::PoseFrame&) { return true; }); });
}

void Worker::CallIkSession() {
  Timed("IkSession", [&] {
    auto session = client_->OpenIkSession(IkStart());
    for (int k = 0; k < 5; ++k) session->MoveTarget(0, 20 + Jitter(6), 30 + Jitter(6), 20 + Jitter(6));
    session->Close();
  });
}

void Worker::CallDeform() {
  v1::DeformRequest r;
  r.set_mesh("soak_grid");                         // an OBJ's one mesh takes the asset's name
  for (int i = 0; i < kGrid; ++i) r.add_fixed(i);  // the bottom row
  auto* h = r.add_handles();
  h->set_index((kGrid - 1) * kGrid + kGrid / 2);  // the top row's middle
  for (double v : {0.5 + Jitter(0.2), 1.0 + Jitter(0.2), 0.2 + Jitter(0.2)}) h->add_position(v);
  Timed("Deform", [&] { client_->Deform(r); });
}

void Worker::CallList() {
  switch (rng_() % 3) {
    case 0: Timed("ListAssets", [&] { client_->ListAssets(); }); break;
    case 1: Timed("ListClips", [&] { client_->ListClips(); }); break;
    default: Timed("ListSkeletons", [&] { client_->ListSkeletons(); });
  }
}

void Worker::CallImportDelete() {
  const std::string name = Name("c");
  bool imported = false;
  Timed("ImportAsset", [&] {
    client_->Import({name + ".bvh", SmallBvh(4)}, name);
    imported = true;
  });
  if (imported) Timed("DeleteAsset", [&] { client_->DeleteAsset(name); });
}

// CreateClip with bake: a three-layer motion sampled into keys, stored, then deleted.
void Worker::CallBake() {
  v1::CreateClipRequest r;
  r.set_name(Name("b"));
  auto* bake = r.mutable_bake();
  *bake->mutable_motion() = ThreeLayers();
  bake->set_fps(30);
  bake->set_duration(1);
  v1::CreateClipResponse answer;
  MakeThenDelete("CreateClip bake", r.name(), [&](grpc::ClientContext& context) {
    return v1::AuthoringService::NewStub(client_->channel())->CreateClip(&context, r, &answer);
  });
}

// demo_walk's clip onto the demo character's skeleton, stored, then deleted.
void Worker::CallRetarget() {
  v1::RetargetClipRequest r;
  r.set_clip("demo_walk");
  r.set_skeleton("demo_character");
  r.set_name(Name("r"));
  v1::RetargetClipResponse answer;
  MakeThenDelete("RetargetClip", r.name(), [&](grpc::ClientContext& context) {
    return v1::AuthoringService::NewStub(client_->channel())->RetargetClip(&context, r, &answer);
  });
}

void Worker::MakeThenDelete(const std::string& method, const std::string& asset,
                            const std::function<grpc::Status(grpc::ClientContext&)>& make) {
  bool made = false;
  TimedStatus(method, [&] {
    grpc::ClientContext context;
    SetDeadline(context);
    const grpc::Status st = make(context);
    made = st.ok();
    return st;
  });
  if (made) Timed("DeleteAsset", [&] { client_->DeleteAsset(asset); });
}

// A quarter second of playback at 60 fps with a crossfade into a second clip.
void Worker::CallPlayback() {
  TimedStatus("PlaybackSession", [&] {
    grpc::ClientContext context;
    SetDeadline(context);
    auto stream = v1::PoseService::NewStub(client_->channel())->PlaybackSession(&context);
    v1::PlaybackCommand start;
    start.mutable_start()->set_skeleton("demo_walk");
    start.mutable_start()->set_fps(60);
    start.mutable_start()->set_duration(0.25);
    start.mutable_start()->mutable_play()->set_clip("demo_walk");
    v1::PlaybackCommand play;
    *play.mutable_play()->mutable_motion() = ThreeLayers();
    play.mutable_play()->set_crossfade(0.1);
    stream->Write(start);
    stream->Write(play);
    stream->WritesDone();
    v1::PlaybackFrame frame;
    int frames = 0;
    while (stream->Read(&frame)) ++frames;
    const grpc::Status st = stream->Finish();
    if (st.ok() && frames < 10)
      return grpc::Status(grpc::StatusCode::UNKNOWN, std::to_string(frames) + " playback frames of 15");
    return st;
  });
}

// An IK drag over the HTTP port's WebSocket, in binary frames.
void Worker::CallWebSocketSession() {
  if (!has_http_) return;
  v1::IkSessionRequest first;
  *first.mutable_start() = IkStart();
  first.mutable_start()->clear_skeleton();  // the path names it
  std::vector<std::string> messages = {first.SerializeAsString()};
  for (int k = 0; k < 5; ++k) {
    v1::IkSessionRequest move;
    auto* t = move.add_targets();
    t->set_effector(0);
    for (double v : {20 + Jitter(6), 30 + Jitter(6), 20 + Jitter(6)}) t->add_target_position(v);
    messages.push_back(move.SerializeAsString());
  }
  TimedStatus("WebSocket IK", [&] { return http_.WebSocketSession("/v1/skeletons/demo_walk:ikSession", messages); });
}

}  // namespace armature::soak
