// IK and deformation sessions over a WebSocket on their REST paths, end to
// end: a real armature-server and a client written here from RFC 6455 (its
// own framing and masking, the RFC's accept key), answers compared with the
// same session over gRPC, in JSON and in binary frames; the handshake's
// errors, the bearer subprotocol, a failed call's status frame and close
// code, and the limits (sessions, the HTTP threads sessions may hold).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>

// Eigen (ik_rig.h) before httplib.h: the resolver header it pulls in defines a macro `_res`.
#include "ik/ik_rig.h"

#include <google/protobuf/util/json_util.h>
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/deform_grid.h"
#include "support/server_process.h"
#include "support/ws_client.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

namespace armature::testing {
namespace {

using google::protobuf::util::MessageDifferencer;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

std::string Json(const google::protobuf::Message& m) {
  std::string out;
  EXPECT_TRUE(google::protobuf::util::MessageToJsonString(m, &out).ok());
  return out;
}

template <typename M>
M FromJson(const std::string& text) {
  M m;
  EXPECT_TRUE(google::protobuf::util::JsonStringToMessage(text, &m).ok()) << text.substr(0, 200);
  return m;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

// The hand dragged along a small circle, the foot planted: IkSessionSpec's drag.
struct IkDrag {
  v1::SolveIkRequest start;
  std::vector<Eigen::Vector3d> path;
};

IkDrag MakeIkDrag(client::Client& client) {
  const Motion m(client, kDemoRig);
  const double t = 0.8;
  const Eigen::Vector3d wrist = m.WorldPosition(t, "LeftWrist"), ankle = m.WorldPosition(t, "RightAnkle");
  IkDrag d;
  d.start.set_skeleton("demo_walk");
  d.start.mutable_from_clip()->set_clip("demo_walk");
  d.start.mutable_from_clip()->set_time(t);
  *d.start.add_effectors() = Effector("LeftWrist", wrist);
  *d.start.add_effectors() = Effector("RightAnkle", ankle);
  for (int i = 1; i <= 40; ++i) {
    const double s = i / 40.0, a = 2 * M_PI * s;
    d.path.push_back(wrist + Eigen::Vector3d(5 * std::sin(a), 15 * s + 5 * (1 - std::cos(a)), 30 * s));
  }
  return d;
}

v1::IkSessionRequest Move(const Eigen::Vector3d& target) {
  v1::IkSessionRequest r;
  auto* u = r.add_targets();
  u->set_effector(0);
  for (int k = 0; k < 3; ++k) u->add_target_position(target[k]);
  return r;
}

class WebSocketSession : public ::testing::Test {
 protected:
  TempDir data_;
};

TEST_F(WebSocketSession, IkSessionAnswersEqualTheGrpcSessionInJsonAndBinaryFrames) {
  ServerProcess server(data_.path());
  client::Client client(OptionsFor(server));
  const IkDrag drag = MakeIkDrag(client);

  for (const bool binary : {false, true}) {
    SCOPED_TRACE(binary ? "binary frames" : "JSON text frames");
    auto grpc_session = client.OpenIkSession(drag.start);
    WsClient ws(server.http_port(), "/v1/skeletons/demo_walk:ikSession");
    ASSERT_EQ(ws.status(), 101);
    EXPECT_EQ(ws.header("Sec-WebSocket-Accept"), kAccept);
    EXPECT_EQ(ws.header("Upgrade"), "websocket");

    v1::IkSessionRequest first;
    *first.mutable_start() = drag.start;
    first.mutable_start()->clear_skeleton();  // the path names it
    auto send = [&](const v1::IkSessionRequest& r) {
      if (binary)
        ws.Send(0x2, r.SerializeAsString());
      else
        ws.SendText(Json(r));
    };
    auto receive = [&]() {
      const Frame f = ws.Receive();
      EXPECT_EQ(f.opcode, binary ? 0x2 : 0x1) << f.payload.substr(0, 200);
      v1::SolveIkResponse answer;
      if (binary)
        EXPECT_TRUE(answer.ParseFromString(f.payload));
      else
        answer = FromJson<v1::SolveIkResponse>(f.payload);
      return answer;
    };
    send(first);
    EXPECT_TRUE(MessageDifferencer::Equals(receive(), grpc_session->last()));

    // Interleaved, so both see the same load: each step over gRPC, then over the WebSocket.
    std::vector<double> grpc_ms, ws_ms;
    for (size_t i = 0; i < drag.path.size(); ++i) {
      const Eigen::Vector3d& p = drag.path[i];
      auto t0 = Clock::now();
      const v1::SolveIkResponse expected = grpc_session->MoveTarget(0, p.x(), p.y(), p.z());
      grpc_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      t0 = Clock::now();
      send(Move(p));
      const v1::SolveIkResponse answer = receive();
      ws_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      ASSERT_TRUE(MessageDifferencer::Equals(answer, expected)) << "update " << i << ":\n"
                                                                << answer.DebugString().substr(0, 400);
    }
    ws.SendClose(1000);
    const Frame close = ws.Receive();
    EXPECT_EQ(close.opcode, 0x8);
    EXPECT_EQ(close.close_code(), 1000);
    EXPECT_TRUE(ws.Closed());
    grpc_session->Close();
    std::printf("  IK drag, %zu steps (%s): round trip median %.3f ms over the WebSocket, %.3f ms over gRPC\n",
                drag.path.size(), binary ? "binary" : "JSON", Median(ws_ms), Median(grpc_ms));
    // In binary frames the WebSocket path adds only framing and a thread hop to the same call:
    // within the issue's 2× of gRPC (JSON adds printing the pose, about 0.3 ms here).
    if (binary) EXPECT_LE(Median(ws_ms), 2 * Median(grpc_ms));
  }
  EXPECT_TRUE(client.Healthy());
}

TEST_F(WebSocketSession, DeformSessionAnswersEqualTheGrpcSession) {
  ServerProcess server(data_.path());
  client::Client client(OptionsFor(server));
  const Grid grid = MakeGrid(17);
  const Edit edit = BumpEdit(grid);
  client.Import({"bump.obj", grid.obj}, "bump");
  v1::DeformSessionStart start;
  start.mutable_setup()->set_mesh("bump");
  for (uint32_t v : edit.fixed) start.mutable_setup()->add_fixed(v);
  for (uint32_t v : edit.handles) start.add_handle_indices(v);
  auto grpc_session = client.OpenDeformSession(start);
  const v1::DeformResponse rest = grpc_session->last();
  ASSERT_EQ(rest.positions_size(), grid.n * grid.n * 3);
  const uint32_t h = edit.handles.at(0);

  WsClient ws(server.http_port(), "/v1/meshes:deformSession");
  ASSERT_EQ(ws.status(), 101);
  v1::DeformSessionRequest first;
  *first.mutable_start() = start;
  ws.SendText(Json(first));
  Frame f = ws.Receive();
  ASSERT_EQ(f.opcode, 0x1) << f.payload.substr(0, 200);
  EXPECT_TRUE(MessageDifferencer::Equals(FromJson<v1::DeformResponse>(f.payload), rest));
  for (int i = 1; i <= 5; ++i) {
    v1::DeformSessionRequest move;
    for (int k = 0; k < 3; ++k) move.mutable_move()->add_positions(rest.positions(h * 3 + k) + 0.02 * i * (k + 1));
    const v1::DeformResponse expected =
        grpc_session->Move(std::vector<double>(move.move().positions().begin(), move.move().positions().end()));
    ws.Send(0x2, move.SerializeAsString());  // binary this time
    f = ws.Receive();
    ASSERT_EQ(f.opcode, 0x2);
    v1::DeformResponse answer;
    ASSERT_TRUE(answer.ParseFromString(f.payload));
    EXPECT_EQ(answer.index(), static_cast<uint64_t>(i));
    EXPECT_TRUE(MessageDifferencer::Equals(answer, expected)) << "move " << i;
  }
  grpc_session->Close();
}

TEST_F(WebSocketSession, AFailedCallEndsWithItsStatusThenACloseFrame) {
  ServerProcess server(data_.path());
  {  // No such skeleton: NOT_FOUND from the service.
    WsClient ws(server.http_port(), "/v1/skeletons/nobody:ikSession");
    ASSERT_EQ(ws.status(), 101);
    ws.SendText(R"({"start": {"effectors": [{"joint": "Head", "targetPosition": [0, 1, 0]}]}})");
    const Frame status = ws.Receive();
    ASSERT_EQ(status.opcode, 0x1);
    const json j = json::parse(status.payload);
    EXPECT_EQ(j["code"], static_cast<int>(grpc::StatusCode::NOT_FOUND));
    EXPECT_NE(j["message"].get<std::string>().find("nobody"), std::string::npos) << j.dump();
    const Frame close = ws.Receive();
    EXPECT_EQ(close.opcode, 0x8);
    EXPECT_EQ(close.close_code(), 4000 + static_cast<int>(grpc::StatusCode::NOT_FOUND));
    EXPECT_TRUE(ws.Closed());
  }
  {  // Malformed JSON: INVALID_ARGUMENT naming the message.
    WsClient ws(server.http_port(), "/v1/skeletons/demo_walk:ikSession");
    ws.SendText(R"({"start": {"effectors": [}})");
    const json j = json::parse(ws.Receive().payload);
    EXPECT_EQ(j["code"], static_cast<int>(grpc::StatusCode::INVALID_ARGUMENT));
    EXPECT_NE(j["message"].get<std::string>().find("message 1"), std::string::npos) << j.dump();
    EXPECT_EQ(ws.Receive().close_code(), 4000 + static_cast<int>(grpc::StatusCode::INVALID_ARGUMENT));
  }
  {  // A protocol error: an unmasked client frame is closed with 1002.
    WsClient ws(server.http_port(), "/v1/skeletons/demo_walk:ikSession");
    ws.SendRaw(std::string("\x81\x02{}", 4));
    const Frame close = ws.Receive();
    EXPECT_EQ(close.opcode, 0x8);
    EXPECT_EQ(close.close_code(), 1002);
    EXPECT_NE(close.payload.find("masked"), std::string::npos);
  }
  {  // A message over --max-request-kb: 1009.
    WsClient ws(server.http_port(), "/v1/skeletons/demo_walk:ikSession");
    ws.SendText(std::string(5 << 20, ' '));
    EXPECT_EQ(ws.Receive().close_code(), 1009);
  }
  {  // Ping is answered with pong, same payload.
    WsClient ws(server.http_port(), "/v1/skeletons/demo_walk:ikSession");
    ws.Send(0x9, "hello");
    const Frame pong = ws.Receive();
    EXPECT_EQ(pong.opcode, 0xA);
    EXPECT_EQ(pong.payload, "hello");
  }
  // Handshake errors are plain HTTP errors with the gateway's JSON.
  EXPECT_EQ(WsClient(server.http_port(), "/v1/skeletons/demo_walk:ikSession", {"Sec-WebSocket-Version: 8"}).status(),
            426);
  WsClient not_a_session(server.http_port(), "/v1/clips/demo_walk:evaluate");
  EXPECT_EQ(not_a_session.status(), 404);
  EXPECT_NE(not_a_session.body().find("ikSession"), std::string::npos) << not_a_session.body();
  client::Client client(OptionsFor(server));
  EXPECT_TRUE(client.Healthy());
}

// httplib reads no body on a GET: an upgrade's body would be read as frames.
TEST_F(WebSocketSession, AnUpgradeWithABodyIsRefused) {
  ServerProcess server(data_.path());
  const std::string path = "/v1/skeletons/demo_walk:ikSession";
  WsClient sized(server.http_port(), path, {"Content-Length: 300000000"});
  EXPECT_EQ(sized.status(), 400);
  EXPECT_NE(sized.body().find("Content-Length: 300000000"), std::string::npos) << sized.body();
  EXPECT_TRUE(sized.Closed());
  WsClient chunked(server.http_port(), path, {"Transfer-Encoding: chunked"});
  EXPECT_EQ(chunked.status(), 400);
  EXPECT_NE(chunked.body().find("Transfer-Encoding"), std::string::npos) << chunked.body();
  EXPECT_EQ(WsClient(server.http_port(), path, {"Content-Length: 0"}).status(), 101);
}

TEST_F(WebSocketSession, TheBearerTokenMayComeAsASubprotocol) {
  const auto token_file = data_.path() / "tokens";
  std::ofstream(token_file) << "ws-secret-1\n";
  ServerProcess server(data_.path() / "data", {"--auth-token-file", token_file.string()});
  const std::string path = "/v1/skeletons/demo_walk:ikSession";
  const std::string first = R"({"start": {"effectors": [{"joint": "LeftWrist", "targetPosition": [10, 100, 10]}]}})";
  EXPECT_EQ(WsClient(server.http_port(), path).status(), 401);
  EXPECT_EQ(WsClient(server.http_port(), path, {"Sec-WebSocket-Protocol: bearer.wrong"}).status(), 401);

  WsClient dotted(server.http_port(), path, {"Sec-WebSocket-Protocol: bearer.ws-secret-1"});
  ASSERT_EQ(dotted.status(), 101);
  EXPECT_EQ(dotted.header("Sec-WebSocket-Protocol"), "bearer.ws-secret-1");
  WsClient pair(server.http_port(), path, {"Sec-WebSocket-Protocol: bearer, ws-secret-1"});
  ASSERT_EQ(pair.status(), 101);
  EXPECT_EQ(pair.header("Sec-WebSocket-Protocol"), "bearer");
  WsClient header(server.http_port(), path, {"Authorization: Bearer ws-secret-1"});
  ASSERT_EQ(header.status(), 101);
  EXPECT_EQ(header.header("Sec-WebSocket-Protocol"), "");
  for (WsClient* ws : {&dotted, &pair, &header}) {
    ws->SendText(first);
    const Frame f = ws->Receive();
    ASSERT_EQ(f.opcode, 0x1);
    EXPECT_TRUE(json::parse(f.payload).contains("world")) << f.payload.substr(0, 200);
  }
}

TEST_F(WebSocketSession, SessionsCountAgainstTheSessionLimit) {
  ServerProcess server(data_.path(), {"--max-sessions", "3"});
  const std::string path = "/v1/skeletons/demo_walk:ikSession";
  const std::string first = R"({"start": {"effectors": [{"joint": "LeftWrist", "targetPosition": [10, 100, 10]}]}})";
  std::vector<std::unique_ptr<WsClient>> open;
  for (int i = 0; i < 3; ++i) {
    open.push_back(std::make_unique<WsClient>(server.http_port(), path));
    open.back()->SendText(first);
    ASSERT_EQ(open.back()->Receive().opcode, 0x1) << "session " << i;
  }
  // --max-sessions 3: the fourth session's call is refused by the service.
  WsClient fourth(server.http_port(), path);
  ASSERT_EQ(fourth.status(), 101);
  fourth.SendText(first);
  const Frame refused = fourth.Receive();
  ASSERT_EQ(refused.opcode, 0x1);
  EXPECT_EQ(json::parse(refused.payload)["code"], static_cast<int>(grpc::StatusCode::RESOURCE_EXHAUSTED));
  EXPECT_NE(refused.payload.find("--max-sessions"), std::string::npos) << refused.payload;
  EXPECT_EQ(fourth.Receive().close_code(), 4000 + static_cast<int>(grpc::StatusCode::RESOURCE_EXHAUSTED));
  EXPECT_TRUE(fourth.Closed());
  // A closed session frees its place.
  open.pop_back();
  EXPECT_TRUE(WaitFor(
      [&] {
        WsClient again(server.http_port(), path);
        again.SendText(first);
        return again.Receive().payload.find("\"world\"") != std::string::npos;
      },
      10));
}

TEST_F(WebSocketSession, SessionsLeaveHttpThreadsForRest) {
  // 16 HTTP threads: the gateway's streams and sessions may hold 12 of them.
  ServerProcess server(data_.path(), {"--http-threads", "16"});
  const std::string path = "/v1/skeletons/demo_walk:ikSession";
  std::vector<std::unique_ptr<WsClient>> open;
  while (open.size() < 12) {
    open.push_back(std::make_unique<WsClient>(server.http_port(), path));
    ASSERT_EQ(open.back()->status(), 101) << "session " << open.size();
  }
  WsClient one_too_many(server.http_port(), path);
  EXPECT_EQ(one_too_many.status(), 429) << one_too_many.body();
  EXPECT_NE(one_too_many.body().find("too many open streams"), std::string::npos) << one_too_many.body();
  // REST still answers while the sessions are open.
  httplib::Client http("127.0.0.1", server.http_port());
  const auto r = http.Post("/v1/clips/demo_walk:evaluate", R"({"times": [0.5]})", "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  // Closed sessions give their threads back.
  open.clear();
  EXPECT_TRUE(WaitFor([&] { return WsClient(server.http_port(), path).status() == 101; }, 10));
}

TEST_F(WebSocketSession, PlaybackSessionStreamsPacedFramesAndTakesCommandsBesideThem) {
  ServerProcess server(data_.path());
  WsClient ws(server.http_port(), "/v1/skeletons/demo_walk:playbackSession");
  ASSERT_EQ(ws.status(), 101);
  // Not one answer per message: frames come at the start's fps until the client closes.
  ws.SendText(R"({"start": {"fps": 60, "space": "WORLD", "play": {"clip": "demo_walk"}}})");
  std::vector<json> frames;
  for (int i = 0; i < 10; ++i) {
    const Frame f = ws.Receive();
    ASSERT_EQ(f.opcode, 0x1) << f.payload.substr(0, 200);
    frames.push_back(json::parse(f.payload));
  }
  ws.SendText(R"({"pause": {}})");  // a command between frames
  for (int i = 0; i < 3; ++i) frames.push_back(json::parse(ws.Receive().payload));
  for (size_t i = 0; i < frames.size(); ++i)
    EXPECT_EQ(frames[i].value("index", std::string("0")), std::to_string(i)) << frames[i].dump().substr(0, 200);
  EXPECT_TRUE(frames[0]["pose"].contains("translations"));
  ws.SendClose(1000);
  // Frames already on their way may come first; then the close.
  Frame f;
  do f = ws.Receive();
  while (f.opcode == 0x1);
  EXPECT_EQ(f.opcode, 0x8);
  EXPECT_EQ(f.close_code(), 1000);
}

// A server over TLS with a self-signed certificate for localhost, and the
// client script `script` (Python's ssl, trusting it) run against it.
CommandResult RunTlsClient(const TempDir& data, const std::string& script) {
  TempDir files;
  const auto cert = files.path() / "server.crt", key = files.path() / "server.key";
  const CommandResult made = RunCommand(
      "openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=localhost"
      " -addext subjectAltName=DNS:localhost,IP:127.0.0.1 -keyout " +
      ShellQuote(key.string()) + " -out " + ShellQuote(cert.string()));
  if (made.exit_code != 0) return made;
  ServerProcess server(data.path(), {"--tls-cert", cert.string(), "--tls-key", key.string()});
  return RunCommand(std::string(ARMATURE_PYTHON) + " " +
                    ShellQuote(std::string(ARMATURE_TEST_DIR) + "/integration/gateway/" + script) + " " +
                    std::to_string(server.http_port()) + " " + ShellQuote(cert.string()));
}

TEST_F(WebSocketSession, RunsOverTls) {
  const CommandResult r = RunTlsClient(data_, "websocket_tls_client.py");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  // The 101, four answers with a pose (the start, three moves), then the server's close 1000.
  EXPECT_EQ(r.out, "HTTP/1.1 101 Switching Protocols\n1 True\n1 True\n1 True\n1 True\n8 1000\n") << r.err;
}

// The session's frames go on while a TLS record from the client is cut in
// half (its reader waits on the socket, never its writer).
TEST_F(WebSocketSession, HalfATlsRecordDoesNotStallTheFrames) {
  const CommandResult r = RunTlsClient(data_, "websocket_tls_half_record.py");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  std::istringstream lines(r.out);
  std::string status, word;
  int stalled = -1;
  std::getline(lines, status);
  lines >> word >> stalled;
  EXPECT_EQ(status, "HTTP/1.1 101 Switching Protocols");
  EXPECT_EQ(word, "stalled");
  // 2 s at 30 fps: about 60 frames; a session whose reader blocks sends none.
  EXPECT_GE(stalled, 20) << r.out;
  EXPECT_NE(r.out.find("pong True"), std::string::npos) << r.out << r.err;
}

}  // namespace
}  // namespace armature::testing
