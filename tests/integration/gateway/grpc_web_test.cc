// gRPC-Web on the HTTP port and binary REST (application/x-protobuf), end to
// end: a real armature-server, requests framed here by hand from the
// protocol text (flag byte, 4-byte big-endian length; trailers as header
// lines) with httplib::Client, answers compared with the same calls over gRPC.
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <map>

#include "armature/client.h"
#include "gateway/grpc_web_call.h"
#include "support/client_helpers.h"
#include "support/metrics_scrape.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

using google::protobuf::util::MessageDifferencer;

constexpr char kToken[] = "grpc-web-token";

template <typename M>
M Parsed(const std::string& bytes) {
  M m;
  EXPECT_TRUE(m.ParseFromString(bytes));
  return m;
}

v1::EvaluateClipRequest EvaluateRequest(const std::string& clip) {
  v1::EvaluateClipRequest req;
  req.set_clip(clip);
  for (double t : {0.0, 0.4, 1.3}) req.add_times(t);
  req.set_space(v1::WORLD);
  return req;
}

class GrpcWeb : public ::testing::Test {
 protected:
  TempDir data_;
};

TEST_F(GrpcWeb, EvaluateClipEqualsTheGrpcAnswerInBinaryAndTextModes) {
  ServerProcess server(data_.path());
  auto http = Http(server);
  client::Client grpc(OptionsFor(server));
  const v1::EvaluateClipRequest req = EvaluateRequest("demo_walk");
  const v1::EvaluateClipResponse expected = grpc.EvaluateClip(req);
  ASSERT_GT(expected.poses_size(), 0);

  for (const std::string type : {"application/grpc-web", "application/grpc-web+proto", "application/grpc-web-text",
                                 "application/grpc-web-text+proto"}) {
    SCOPED_TRACE(type);
    const bool text = type.find("-text") != std::string::npos;
    const auto a = Call(http, "/armature.v1.PoseService/EvaluateClip", Frame(req.SerializeAsString()), text, {}, type);
    EXPECT_EQ(a.http_status, 200);
    EXPECT_EQ(a.content_type, text ? "application/grpc-web-text+proto" : "application/grpc-web+proto");
    ASSERT_EQ(a.messages.size(), 1u);
    EXPECT_EQ(a.trailer_frames, 1);
    EXPECT_EQ(a.code(), 0);
    EXPECT_EQ(a.message(), "");
    EXPECT_TRUE(MessageDifferencer::Equals(Parsed<v1::EvaluateClipResponse>(a.messages[0]), expected));
  }
}

TEST_F(GrpcWeb, StreamClipSendsEveryFrameTheGrpcStreamSends) {
  ServerProcess server(data_.path());
  auto http = Http(server);
  client::Client grpc(OptionsFor(server));
  v1::StreamClipRequest req;
  req.set_clip("demo_walk");
  req.set_fps(240);
  req.set_speed(8);  // the whole clip in a fraction of its length
  req.set_space(v1::WORLD);

  std::vector<v1::PoseFrame> expected;
  {
    grpc::ClientContext context;
    auto reader = v1::PoseService::NewStub(grpc.channel())->StreamClip(&context, req);
    v1::PoseFrame frame;
    while (reader->Read(&frame)) expected.push_back(frame);
    ASSERT_TRUE(reader->Finish().ok());
  }
  ASSERT_GT(expected.size(), 5u);

  for (const bool text : {false, true}) {
    SCOPED_TRACE(text ? "text" : "binary");
    const auto a = Call(http, "/armature.v1.PoseService/StreamClip", Frame(req.SerializeAsString()), text);
    EXPECT_EQ(a.http_status, 200);
    EXPECT_EQ(a.code(), 0) << a.message();
    EXPECT_EQ(a.trailer_frames, 1);
    ASSERT_EQ(a.messages.size(), expected.size());
    for (size_t i = 0; i < expected.size(); ++i) {
      v1::PoseFrame got = Parsed<v1::PoseFrame>(a.messages[i]), want = expected[i];
      // Wall-clock fields differ between two runs; the poses must not.
      MessageDifferencer diff;
      for (const auto* field : {"sent_at_unix_nanos", "wall_time"})
        if (const auto* f = v1::PoseFrame::descriptor()->FindFieldByName(field)) diff.IgnoreField(f);
      EXPECT_TRUE(diff.Compare(got, want)) << i << ": " << got.ShortDebugString() << "\nvs " << want.ShortDebugString();
    }
  }
}

TEST_F(GrpcWeb, ErrorsArriveAsTrailersWithTheMessage) {
  ServerProcess server(data_.path());
  auto http = Http(server);
  const auto missing =
      Call(http, "/armature.v1.PoseService/EvaluateClip", Frame(EvaluateRequest("no such clip%").SerializeAsString()));
  EXPECT_EQ(missing.http_status, 200);
  EXPECT_TRUE(missing.messages.empty());
  EXPECT_EQ(missing.code(), 5);
  EXPECT_NE(missing.message().find("no such clip%"), std::string::npos) << missing.message();

  const auto text = Call(http, "/armature.v1.PoseService/EvaluateClip",
                         Frame(EvaluateRequest("no such clip").SerializeAsString()), true);
  EXPECT_EQ(text.code(), 5);
  EXPECT_NE(text.message().find("no such clip"), std::string::npos) << text.message();

  // Validation runs as over gRPC: a negative time names the field.
  v1::EvaluateClipRequest bad = EvaluateRequest("demo_walk");
  bad.set_times(0, -1);
  const auto invalid = Call(http, "/armature.v1.PoseService/EvaluateClip", Frame(bad.SerializeAsString()));
  EXPECT_EQ(invalid.code(), 3);
  EXPECT_NE(invalid.message().find("times"), std::string::npos) << invalid.message();
}

TEST_F(GrpcWeb, MalformedRequestsAreRefusedWithAStatus) {
  ServerProcess server(data_.path());
  auto http = Http(server);
  const std::string path = "/armature.v1.PoseService/EvaluateClip";
  const std::string message = EvaluateRequest("demo_walk").SerializeAsString();
  struct Case {
    std::string body;
    int code;
    std::string fragment;
  };
  const Case cases[] = {
      {Frame(message).substr(0, 3), 3, "too few for the 5-byte header"},
      {Frame(message).substr(0, 20), 3, "only 15 follow"},
      {std::string("\x00\x7f\xff\xff\xff", 5) + "abc", 8, "exceeds the limit"},
      {Frame(message, 0x01), 12, "compressed messages are not supported"},
      {Frame(message, 0x80), 3, "trailer frame"},
      {"", 3, "exactly one message frame, got 0"},
      {Frame(message) + Frame(message), 3, "exactly one message frame, got 2"},
      {Frame("\xff\xff\xff"), 3, "not a valid armature.v1.EvaluateClipRequest encoding"},
  };
  for (const auto& c : cases) {
    const auto a = Call(http, path, c.body);
    EXPECT_EQ(a.http_status, 200);
    EXPECT_EQ(a.code(), c.code) << a.message();
    EXPECT_NE(a.message().find(c.fragment), std::string::npos) << a.message();
  }
  const auto bad_base64 = http.Post(path, "not*base64", "application/grpc-web-text");
  ASSERT_TRUE(bad_base64);
  EXPECT_NE(FromBase64(bad_base64->body).find("grpc-status: 3"), std::string::npos);

  // Streams of requests need a transport that carries them.
  const auto bidi = Call(http, "/armature.v1.IkService/IkSession", Frame(""));
  EXPECT_EQ(bidi.code(), 12);
  EXPECT_NE(bidi.message().find("WebSocket"), std::string::npos) << bidi.message();
  const auto unknown = Call(http, "/armature.v1.PoseService/Dance", Frame(""));
  EXPECT_EQ(unknown.code(), 12);
  EXPECT_NE(unknown.message().find("/armature.v1.PoseService/Dance"), std::string::npos);
  // Not gRPC-Web at all: a plain HTTP error.
  const auto json = http.Post(path, "{}", "application/json");
  ASSERT_TRUE(json);
  EXPECT_EQ(json->status, 415);
  EXPECT_NE(json->body.find("application/grpc-web"), std::string::npos);
  // The connection is still good for the next request.
  EXPECT_EQ(Call(http, path, Frame(message)).code(), 0);
}

TEST_F(GrpcWeb, AuthLimitsAndCorsAreTheGatewayOnes) {
  TempDir files;
  const auto tokens = WriteTemp(files, "tokens", std::string(kToken) + "\n");
  ServerProcess server(data_.path(), {"--auth-token-file", tokens.string(), "--cors-origin", "http://app.example",
                                      "--max-request-kb", "1"});
  auto http = Http(server);
  const std::string path = "/armature.v1.AssetService/ListClips";
  const auto none = Call(http, path, Frame(""));
  EXPECT_EQ(none.code(), 16);
  EXPECT_NE(none.message().find("Bearer"), std::string::npos) << none.message();
  const auto wrong = Call(http, path, Frame(""), false, {{"Authorization", "Bearer nope"}});
  EXPECT_EQ(wrong.code(), 16);
  const auto good = Call(http, path, Frame(""), false, {{"Authorization", std::string("Bearer ") + kToken}});
  EXPECT_EQ(good.code(), 0) << good.message();
  ASSERT_EQ(good.messages.size(), 1u);
  EXPECT_EQ(Parsed<v1::ListClipsResponse>(good.messages[0]).clips_size(), 2);

  // --max-request-kb bounds the message.
  v1::EvaluateClipRequest big = EvaluateRequest("demo_walk");
  for (int i = 0; i < 200; ++i) big.add_times(0.01 * i);
  const auto too_big = Call(http, "/armature.v1.PoseService/EvaluateClip", Frame(big.SerializeAsString()), false,
                            {{"Authorization", std::string("Bearer ") + kToken}});
  EXPECT_EQ(too_big.code(), 8);
  EXPECT_NE(too_big.message().find("--max-request-kb"), std::string::npos) << too_big.message();

  const auto preflight =
      http.Options(path, {{"Origin", "http://app.example"},
                          {"Access-Control-Request-Method", "POST"},
                          {"Access-Control-Request-Headers", "content-type,x-grpc-web,x-user-agent"}});
  ASSERT_TRUE(preflight);
  EXPECT_EQ(preflight->status, 204);
  EXPECT_EQ(preflight->get_header_value("Access-Control-Allow-Methods"), "POST, OPTIONS");
  const std::string allowed = preflight->get_header_value("Access-Control-Allow-Headers");
  for (const char* h : {"x-grpc-web", "x-user-agent", "content-type", "authorization"})
    EXPECT_NE(allowed.find(h), std::string::npos) << h << " in " << allowed;
  const auto r = http.Post(path, {{"Origin", "http://app.example"}, {"Authorization", std::string("Bearer ") + kToken}},
                           Frame(""), "application/grpc-web+proto");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->get_header_value("Access-Control-Allow-Origin"), "http://app.example");
  const std::string exposed = r->get_header_value("Access-Control-Expose-Headers");
  EXPECT_NE(exposed.find("grpc-status"), std::string::npos) << exposed;
  EXPECT_NE(exposed.find("grpc-message"), std::string::npos) << exposed;
}

TEST_F(GrpcWeb, BinaryRestTakesAndGivesProtobuf) {
  ServerProcess server(data_.path());
  auto http = Http(server);
  client::Client grpc(OptionsFor(server));
  v1::EvaluateClipRequest body = EvaluateRequest("overridden by the path");
  const v1::EvaluateClipResponse expected = grpc.EvaluateClip(EvaluateRequest("demo_walk"));

  const auto r = http.Post("/v1/clips/demo_walk:evaluate", {{"Accept", "application/x-protobuf"}},
                           body.SerializeAsString(), "application/x-protobuf");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->get_header_value("Content-Type"), "application/x-protobuf");
  EXPECT_TRUE(MessageDifferencer::Equals(Parsed<v1::EvaluateClipResponse>(r->body), expected));

  // Protobuf in, JSON out (no Accept), and JSON in, protobuf out.
  const auto json_out = http.Post("/v1/clips/demo_walk:evaluate", body.SerializeAsString(), "application/x-protobuf");
  ASSERT_EQ(json_out->status, 200) << json_out->body;
  EXPECT_EQ(json_out->get_header_value("Content-Type"), "application/json");
  EXPECT_EQ(nlohmann::json::parse(json_out->body)["poses"].size(), static_cast<size_t>(expected.poses_size()));
  const auto proto_out = http.Post("/v1/clips/demo_walk:evaluate", {{"Accept", "application/x-protobuf"}},
                                   R"({"times":[0,0.4,1.3],"space":"WORLD"})", "application/json");
  ASSERT_EQ(proto_out->status, 200);
  EXPECT_TRUE(MessageDifferencer::Equals(Parsed<v1::EvaluateClipResponse>(proto_out->body), expected));

  const auto list = http.Get("/v1/clips", {{"Accept", "application/x-protobuf"}});
  ASSERT_EQ(list->status, 200);
  EXPECT_TRUE(MessageDifferencer::Equals(Parsed<v1::ListClipsResponse>(list->body), grpc.ListClips()));

  // Errors stay JSON.
  const auto missing = http.Post("/v1/clips/nope:evaluate", {{"Accept", "application/x-protobuf"}},
                                 body.SerializeAsString(), "application/x-protobuf");
  EXPECT_EQ(missing->status, 404);
  EXPECT_EQ(missing->get_header_value("Content-Type"), "application/json");
  const auto garbage = http.Post("/v1/clips/demo_walk:evaluate", {{"Accept", "application/x-protobuf"}},
                                 std::string("\xff\xff\xff"), "application/x-protobuf");
  EXPECT_EQ(garbage->status, 400);
  EXPECT_NE(garbage->body.find("not a valid armature.v1.EvaluateClipRequest encoding"), std::string::npos)
      << garbage->body;
}

// A looping stream over gRPC-Web whose client vanishes: its call is
// cancelled (the next frame's write fails), as the metrics show; calls count
// in the same metrics as gRPC ones.
TEST_F(GrpcWeb, CallsCountInTheMetricsAndAVanishedStreamClientCancelsItsCall) {
  ServerProcess server(data_.path());
  auto http = Http(server);
  const std::string evaluated =
      R"(armature_rpc_requests_total{method="armature.v1.PoseService/EvaluateClip",code="OK"})";
  const double before = std::max(0.0, ScrapeSample(server, evaluated));
  for (int i = 0; i < 3; ++i)
    ASSERT_EQ(
        Call(http, "/armature.v1.PoseService/EvaluateClip", Frame(EvaluateRequest("demo_walk").SerializeAsString()))
            .code(),
        0);
  EXPECT_EQ(ScrapeSample(server, evaluated), before + 3);

  v1::StreamClipRequest req;
  req.set_clip("demo_walk");
  req.set_fps(60);
  req.set_loop(true);
  const std::string body = Frame(req.SerializeAsString());
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(server.http_port()));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  const std::string request =
      "POST /armature.v1.PoseService/StreamClip HTTP/1.1\r\nHost: localhost\r\n"
      "Content-Type: application/grpc-web+proto\r\nContent-Length: " +
      std::to_string(body.size()) + "\r\n\r\n" + body;
  ASSERT_EQ(::send(fd, request.data(), request.size(), MSG_NOSIGNAL), static_cast<ssize_t>(request.size()));
  std::string got;
  char buf[4096];
  while (got.size() < 2000) {  // a few frames
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    ASSERT_GT(n, 0) << got;
    got.append(buf, static_cast<size_t>(n));
  }
  EXPECT_NE(got.find("Transfer-Encoding: chunked"), std::string::npos) << got.substr(0, 300);
  const std::string streaming = R"(armature_rpc_in_flight{method="armature.v1.PoseService/StreamClip"})";
  EXPECT_EQ(ScrapeSample(server, streaming), 1);
  ::close(fd);
  EXPECT_TRUE(WaitFor([&] { return ScrapeSample(server, streaming) == 0; }, 30))
      << "the stream's call was not cancelled when its client went away";
  EXPECT_EQ(ScrapeSample(
                server, R"(armature_rpc_requests_total{method="armature.v1.PoseService/StreamClip",code="CANCELLED"})"),
            1);
}

}  // namespace
}  // namespace armature::testing
