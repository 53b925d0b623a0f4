// Replays a session's requests over gRPC and measures each answer's round
// trip, for the browser test that compares the viewer's WebSocket sessions
// with gRPC on the same server (web/test/session_e2e.mjs):
//   session_replay <host:port> ik|deform <requests.jsonl> [repeats]
// Each line is one request message as JSON (IkSessionRequest or
// DeformSessionRequest); the first opens the session, and the session is
// replayed `repeats` times (default 1). Prints {"roundTripsMs": [...]}: one
// figure per request after the first, every repeat; exits 1 on any error.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include <google/protobuf/util/json_util.h>
#include <grpcpp/grpcpp.h>

#include "armature/v1/deform.grpc.pb.h"
#include "armature/v1/ik.grpc.pb.h"

namespace {

namespace v1 = armature::v1;

template <typename Request, typename Response, typename Open>
bool Replay(const std::vector<std::string>& lines, Open open, std::vector<double>* ms) {
  std::vector<Request> requests(lines.size());
  for (size_t i = 0; i < lines.size(); ++i) {
    if (auto st = google::protobuf::util::JsonStringToMessage(lines[i], &requests[i]); !st.ok()) {
      std::cerr << "line " << i + 1 << ": " << st.ToString() << "\n";
      return false;
    }
  }
  grpc::ClientContext context;
  auto stream = open(&context);
  Response answer;
  for (size_t i = 0; i < requests.size(); ++i) {
    const auto start = std::chrono::steady_clock::now();
    if (!stream->Write(requests[i]) || !stream->Read(&answer)) break;
    if (i > 0)
      ms->push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  stream->WritesDone();
  const grpc::Status status = stream->Finish();
  if (!status.ok()) std::cerr << "the session failed: " << status.error_message() << "\n";
  return status.ok() && ms->size() % (requests.size() - 1) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::cerr << "usage: session_replay <host:port> ik|deform <requests.jsonl> [repeats]\n";
    return 2;
  }
  const std::string kind = argv[2];
  std::ifstream in(argv[3]);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (line.find_first_not_of(" \t\r") != std::string::npos) lines.push_back(line);
  if (lines.size() < 2 || (kind != "ik" && kind != "deform")) {
    std::cerr << "need ik or deform, and a file of at least two requests\n";
    return 2;
  }
  const int repeats = argc > 4 ? std::max(1, std::atoi(argv[4])) : 1;
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(64 << 20);
  auto channel = grpc::CreateCustomChannel(argv[1], grpc::InsecureChannelCredentials(), args);
  std::vector<double> ms;
  for (int r = 0; r < repeats; ++r) {
    const bool ok =
        kind == "ik"
            ? Replay<v1::IkSessionRequest, v1::SolveIkResponse>(
                  lines, [&](grpc::ClientContext* c) { return v1::IkService::NewStub(channel)->IkSession(c); }, &ms)
            : Replay<v1::DeformSessionRequest, v1::DeformResponse>(
                  lines, [&](grpc::ClientContext* c) { return v1::DeformService::NewStub(channel)->DeformSession(c); },
                  &ms);
    if (!ok) return 1;
  }
  std::printf("{\"roundTripsMs\": [");
  for (size_t i = 0; i < ms.size(); ++i) std::printf("%s%.4f", i ? ", " : "", ms[i]);
  std::printf("]}\n");
  return 0;
}
