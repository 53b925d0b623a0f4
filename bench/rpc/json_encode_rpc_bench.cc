// The REST gateway's JSON encoding (server/host/gateway/rest/json/json_writer)
// against protobuf's binary encoding of the same answers, in the same run:
// EvaluateClip of 10,000 times of demo_walk and SkinCharacter of
// RobotExpressive (../shared/data; skipped when absent), each as
//   _Json      the gateway's writer,
//   _Protobuf  the binary encoding (SerializeToString), the baseline,
//   _ProtobufJson  protobuf's MessageToJsonString, the writer it replaced.
// Counters: MB/s of output (bytes_per_second), answer_MB, and peak_x_answer:
// the peak of heap bytes allocated while encoding once, over the answer's
// size; the JSON rows also x_binary_time and x_binary_peak, their time and
// peak over the binary encoding's in the same run.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <functional>
#include <string>

#include <benchmark/benchmark.h>
#include <google/protobuf/util/json_util.h>

#include "armature/v1/meshes.grpc.pb.h"
#include "heap_peak.h"
#include "rpc_bench_server.h"
#include "server/host/gateway/rest/json/json_codec.h"

namespace {

namespace fs = std::filesystem;
namespace pb = google::protobuf;
using armature_bench::Server;

std::string WriterJson(const pb::Message& m) { return armature::server::gateway::MessageToJson(m); }
std::string BinaryEncoding(const pb::Message& m) { return m.SerializeAsString(); }
std::string ProtobufJson(const pb::Message& m) {
  pb::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;
  std::string out;
  (void)pb::util::MessageToJsonString(m, &out, options);
  return out;
}

using Encoder = std::string (*)(const pb::Message&);

double SecondsOf(const pb::Message& answer, Encoder encode) {
  double best = 1e30;
  for (int i = 0; i < 3; ++i) {
    const auto start = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(encode(answer).size());
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return best;
}

// The JSON encoders also report their time and peak memory over the binary
// encoding's, measured here in the same run (x_binary_time, x_binary_peak).
void Encode(benchmark::State& state, const pb::Message& answer, Encoder encode) {
  size_t bytes = 0;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    const std::string out = encode(answer);
    bytes = out.size();
    benchmark::DoNotOptimize(out.data());
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * bytes));
  state.counters["answer_MB"] = static_cast<double>(bytes) / 1e6;
  const double peak = armature_bench::PeakHeapBytesOf([&] { benchmark::DoNotOptimize(encode(answer).size()); });
  state.counters["peak_x_answer"] = peak / static_cast<double>(bytes);
  if (encode == BinaryEncoding) return;
  state.counters["x_binary_time"] =
      seconds / static_cast<double>(state.iterations()) / SecondsOf(answer, BinaryEncoding);
  state.counters["x_binary_peak"] =
      peak / armature_bench::PeakHeapBytesOf([&] { benchmark::DoNotOptimize(BinaryEncoding(answer).size()); });
}

const armature::v1::EvaluateClipResponse& EvaluateClip10k() {
  static const armature::v1::EvaluateClipResponse answer = [] {
    armature::v1::EvaluateClipRequest r;
    r.set_clip("demo_walk");
    for (int i = 0; i < 10000; ++i) r.add_times(i / 60.0);
    return Server().client->EvaluateClip(r);
  }();
  return answer;
}

// Empty when RobotExpressive is not in the shared data.
const armature::v1::SkinCharacterResponse& RobotSkinCharacter() {
  static const armature::v1::SkinCharacterResponse answer = [] {
    armature::v1::SkinCharacterResponse response;
    const fs::path glb = fs::path(ARMATURE_SHARED_DATA) / "gltf/RobotExpressive/RobotExpressive.glb";
    if (!fs::exists(glb)) return response;
    const auto imported = Server().client->ImportFile(glb, "robot");
    armature::v1::SkinCharacterRequest request;
    for (const auto& clip : imported.asset().clips())
      if (clip.name().ends_with("Running")) request.set_clip(clip.name()), request.set_skeleton(clip.skeleton());
    request.set_time(0.37);
    auto stub = armature::v1::MeshService::NewStub(Server().client->channel());
    grpc::ClientContext context;
    (void)stub->SkinCharacter(&context, request, &response);
    return response;
  }();
  return answer;
}

void BM_EvaluateClip10k_Json(benchmark::State& s) { Encode(s, EvaluateClip10k(), WriterJson); }
void BM_EvaluateClip10k_Protobuf(benchmark::State& s) { Encode(s, EvaluateClip10k(), BinaryEncoding); }
void BM_EvaluateClip10k_ProtobufJson(benchmark::State& s) { Encode(s, EvaluateClip10k(), ProtobufJson); }
BENCHMARK(BM_EvaluateClip10k_Json)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EvaluateClip10k_Protobuf)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EvaluateClip10k_ProtobufJson)->Unit(benchmark::kMillisecond);

void Robot(benchmark::State& s, Encoder encode) {
  if (RobotSkinCharacter().meshes_size() == 0)
    return s.SkipWithError("../shared/data/gltf/RobotExpressive/RobotExpressive.glb not present");
  Encode(s, RobotSkinCharacter(), encode);
}
void BM_SkinCharacterRobot_Json(benchmark::State& s) { Robot(s, WriterJson); }
void BM_SkinCharacterRobot_Protobuf(benchmark::State& s) { Robot(s, BinaryEncoding); }
void BM_SkinCharacterRobot_ProtobufJson(benchmark::State& s) { Robot(s, ProtobufJson); }
BENCHMARK(BM_SkinCharacterRobot_Json)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SkinCharacterRobot_Protobuf)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SkinCharacterRobot_ProtobufJson)->Unit(benchmark::kMillisecond);

}  // namespace
