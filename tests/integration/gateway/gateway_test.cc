// The REST/JSON gateway end to end: a real armature-server, HTTP through
// httplib::Client (and raw sockets for clients that misbehave), numbers
// checked against the gRPC path and against hand-derived values.
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <thread>

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "common/sse_events.h"
#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// A two-joint chain written by the test: the root slides from x=0 to x=2
// while the child turns 90° about X, over one second.
constexpr char kChainBvh[] = R"(HIERARCHY
ROOT Root
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Mid
  {
    OFFSET 0 1 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 1 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 1.0
0 0 0 0 0 0 0 0 0
2 0 0 0 0 0 0 90 0
)";

httplib::Client Http(const ServerProcess& server) {
  httplib::Client http("127.0.0.1", server.http_port());
  http.set_read_timeout(60);
  http.set_write_timeout(60);
  return http;
}

client::Client GrpcClient(const ServerProcess& server) {
  client::ClientOptions o;
  o.target = server.target();
  o.timeout = std::chrono::seconds(30);
  return client::Client(o);
}

json Body(const httplib::Result& r) { return json::parse(r->body); }

// An error response: the HTTP status and the {"code","message","details"} shape.
void ExpectError(const httplib::Result& r, int http_status, grpc::StatusCode code, const std::string& fragment) {
  ASSERT_TRUE(r) << "no response";
  EXPECT_EQ(r->status, http_status) << r->body;
  EXPECT_EQ(r->get_header_value("Content-Type"), "application/json");
  const json j = Body(r);
  ASSERT_TRUE(j.is_object()) << r->body;
  EXPECT_EQ(j.size(), 3u) << r->body;
  EXPECT_EQ(j.value("code", -1), static_cast<int>(code)) << r->body;
  EXPECT_NE(j.value("message", std::string()).find(fragment), std::string::npos)
      << "message lacks '" << fragment << "': " << r->body;
  EXPECT_TRUE(j["details"].is_array() && j["details"].empty()) << r->body;
}

// A JSON array of numbers as floats, the way a JSON client reads them.
std::vector<float> Floats(const json& array) {
  std::vector<float> out;
  for (const auto& v : array) out.push_back(static_cast<float>(v.get<double>()));
  return out;
}

std::vector<float> Floats(const google::protobuf::RepeatedField<float>& field) { return {field.begin(), field.end()}; }

// A raw HTTP/1.1 client socket, for clients that stop reading or vanish.
class RawClient {
 public:
  explicit RawClient(int port) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) throw std::runtime_error("connect");
  }
  ~RawClient() { Close(); }
  void Send(const std::string& s) { (void)::send(fd_, s.data(), s.size(), MSG_NOSIGNAL); }
  // Reads until `marker` has arrived (or the peer closes); returns all read.
  std::string ReadUntil(const std::string& marker) {
    std::string got;
    char buf[4096];
    while (got.find(marker) == std::string::npos) {
      const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
      if (n <= 0) break;
      got.append(buf, static_cast<size_t>(n));
    }
    return got;
  }
  void Close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }

 private:
  int fd_ = -1;
};

class Gateway : public ::testing::Test {
 protected:
  fs::path WriteFile(const std::string& name, const std::string& content) {
    const fs::path p = files_.path() / name;
    std::ofstream(p, std::ios::binary) << content;
    return p;
  }
  TempDir data_;
  TempDir files_;
};

TEST_F(Gateway, ListAndGetGiveWhatGrpcGives) {
  ServerProcess server(data_.path());
  auto http = Http(server);
  client::Client grpc = GrpcClient(server);

  const auto list = http.Get("/v1/clips");
  ASSERT_TRUE(list);
  ASSERT_EQ(list->status, 200) << list->body;
  EXPECT_EQ(list->get_header_value("Content-Type"), "application/json");
  const json clips = Body(list)["clips"];
  const auto grpc_clips = grpc.ListClips();
  ASSERT_EQ(clips.size(), static_cast<size_t>(grpc_clips.clips_size()));
  ASSERT_GE(clips.size(), 1u);
  EXPECT_EQ(clips[0]["name"], grpc_clips.clips(0).name());
  EXPECT_EQ(clips[0]["duration"].get<double>(), grpc_clips.clips(0).duration());
  EXPECT_EQ(clips[0]["frames"].get<int>(), grpc_clips.clips(0).frames());
  // lowerCamelCase names, enums by name, defaults printed.
  EXPECT_EQ(clips[0]["frameTime"].get<double>(), grpc_clips.clips(0).frame_time());
  EXPECT_EQ(clips[0]["interpolation"], "LINEAR");
  EXPECT_TRUE(clips[0].contains("joints"));

  const auto skeleton = http.Get("/v1/skeletons/demo_walk");
  ASSERT_EQ(skeleton->status, 200) << skeleton->body;
  const json joints = Body(skeleton)["joints"];
  const auto grpc_skeleton = grpc.GetSkeleton("demo_walk");
  ASSERT_EQ(joints.size(), static_cast<size_t>(grpc_skeleton.joints_size()));
  int end_sites = 0;
  for (int i = 0; i < grpc_skeleton.joints_size(); ++i) {
    EXPECT_EQ(joints[i]["name"], grpc_skeleton.joints(i).name());
    EXPECT_EQ(joints[i]["parent"].get<int>(), grpc_skeleton.joints(i).parent());  // -1 for the root: printed
    EXPECT_EQ(Floats(joints[i]["offset"]), Floats(grpc_skeleton.joints(i).offset()));
    EXPECT_EQ(Floats(joints[i]["endSite"]), Floats(grpc_skeleton.joints(i).end_site()));
    end_sites += !joints[i]["endSite"].empty();
  }
  EXPECT_GT(end_sites, 0);

  const auto clip = http.Get("/v1/clips/demo_walk");
  ASSERT_EQ(clip->status, 200);
  EXPECT_EQ(Body(clip)["joints"].size(), static_cast<size_t>(grpc_skeleton.joints_size()));
}

TEST_F(Gateway, EvaluateGivesTheSameNumbersAsGrpc) {
  ServerProcess server(data_.path());
  auto http = Http(server);
  client::Client grpc = GrpcClient(server);

  for (const std::string space : {"WORLD", "LOCAL"}) {
    const auto r = http.Post("/v1/clips/demo_walk:evaluate",
                             R"({"times":[0,0.5,1.25,2.9],"space":")" + space + R"(","interpolation":"CUBIC"})",
                             "application/json");
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 200) << r->body;
    const json j = Body(r);

    v1::EvaluateClipRequest req;
    req.set_clip("demo_walk");
    for (double t : {0.0, 0.5, 1.25, 2.9}) req.add_times(t);
    req.set_space(space == "WORLD" ? v1::WORLD : v1::LOCAL);
    req.set_interpolation(v1::CUBIC);
    const auto expected = grpc.EvaluateClip(req);

    EXPECT_EQ(j["space"], space);
    EXPECT_EQ(j["skeleton"], expected.skeleton());
    ASSERT_EQ(j["poses"].size(), static_cast<size_t>(expected.poses_size()));
    ASSERT_EQ(j["joints"].size(), static_cast<size_t>(expected.joints_size()));
    for (int p = 0; p < expected.poses_size(); ++p) {
      // Bit for bit: the JSON numbers parse back to the very floats gRPC sends.
      EXPECT_EQ(Floats(j["poses"][p]["translations"]), Floats(expected.poses(p).translations())) << space << p;
      EXPECT_EQ(Floats(j["poses"][p]["rotations"]), Floats(expected.poses(p).rotations())) << space << p;
      EXPECT_EQ(Floats(j["poses"][p]["scales"]), Floats(expected.poses(p).scales())) << space << p;
    }
  }
  // Proto field names work too, and enums by number.
  const auto r =
      http.Post("/v1/clips/demo_walk:evaluate", R"({"times":[0.5],"space":2,"joints":["Hips"]})", "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(Body(r)["space"], "WORLD");
  EXPECT_EQ(Body(r)["joints"], json::array({0}));
}

TEST_F(Gateway, ImportEvaluateAndDeleteAnAssetOverRest) {
  ServerProcess server(data_.path(), {"--no-demo"});
  auto http = Http(server);

  // The raw file is the body; the other fields are query parameters. Kept
  // exact: the pose below is checked to 1e-6, finer than the default bound.
  auto imported = http.Post("/v1/assets:import?filename=chain.bvh&name=chain&precision=exact", kChainBvh,
                            "application/octet-stream");
  ASSERT_EQ(imported->status, 200) << imported->body;
  const json asset = Body(imported)["asset"];
  EXPECT_EQ(asset["name"], "chain");
  EXPECT_EQ(asset["format"], "bvh");
  EXPECT_EQ(asset["sizeBytes"], std::to_string(std::string(kChainBvh).size()));  // int64: a JSON string
  ASSERT_EQ(asset["clips"].size(), 1u);
  EXPECT_EQ(asset["clips"][0]["frames"], 2);
  EXPECT_EQ(asset["clips"][0]["exact"], true);

  ExpectError(http.Post("/v1/assets:import?filename=chain.bvh&name=chain", kChainBvh, "application/octet-stream"), 409,
              grpc::StatusCode::ALREADY_EXISTS, "chain");
  ExpectError(http.Post("/v1/assets:import?filename=bad.bvh", "HIERARCHY\nROOT\n", "application/octet-stream"), 400,
              grpc::StatusCode::INVALID_ARGUMENT, "line");

  // Halfway: the root at x=1; the child one up from it, turned 45° about X.
  const auto r = http.Post("/v1/clips/chain:evaluate", R"({"times":[0.5],"space":"WORLD"})", "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  const json pose = Body(r)["poses"][0];
  const std::vector<double> translations = {1, 0, 0, 1, 1, 0};
  const double c = std::cos(M_PI / 8), s = std::sin(M_PI / 8);
  const std::vector<double> rotations = {1, 0, 0, 0, c, s, 0, 0};
  ASSERT_EQ(pose["translations"].size(), translations.size());
  ASSERT_EQ(pose["rotations"].size(), rotations.size());
  for (size_t i = 0; i < translations.size(); ++i)
    EXPECT_NEAR(pose["translations"][i].get<double>(), translations[i], 1e-6);
  for (size_t i = 0; i < rotations.size(); ++i) EXPECT_NEAR(pose["rotations"][i].get<double>(), rotations[i], 1e-6);

  const auto deleted = http.Delete("/v1/clips/chain");  // additional binding of DeleteAsset
  ASSERT_EQ(deleted->status, 200) << deleted->body;
  EXPECT_EQ(Body(deleted)["name"], "chain");
  ExpectError(http.Get("/v1/clips/chain"), 404, grpc::StatusCode::NOT_FOUND, "chain");
}

TEST_F(Gateway, LargeImportReachesTheServerInChunks) {
  // Over a MiB of motion: the gateway cuts the body into 1 MiB messages.
  std::string bvh = std::string(kChainBvh).substr(0, std::string(kChainBvh).find("MOTION"));
  const int frames = 80000;
  bvh += "MOTION\nFrames: " + std::to_string(frames) + "\nFrame Time: 0.01\n";
  for (int i = 0; i < frames; ++i) bvh += std::to_string(i % 7) + " 0 0 0 0 0 0 " + std::to_string(i % 90) + " 0\n";
  ASSERT_GT(bvh.size(), 1u << 20);
  ServerProcess server(data_.path(), {"--no-demo"});
  auto http = Http(server);
  const auto r = http.Post("/v1/assets:import?filename=long.bvh", bvh, "application/octet-stream");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(Body(r)["asset"]["sizeBytes"], std::to_string(bvh.size()));
  EXPECT_EQ(Body(r)["asset"]["clips"][0]["frames"], frames);
}

TEST_F(Gateway, StreamIsServerSentEventsAtTheRequestedRate) {
  ServerProcess server(data_.path());
  auto http = Http(server);
  client::Client grpc = GrpcClient(server);
  const double fps = 20, speed = 0.5, duration = 1;
  // Repeated fields as repeated parameters, enums by name.
  const std::string path =
      "/v1/clips/demo_walk:stream?fps=20&speed=0.5&duration=1&startTime=0.25&space=WORLD"
      "&joints=Hips&joints=Head";
  std::string text;
  std::string content_type;
  const auto r = http.Get(
      path, httplib::Headers{},
      [&](const httplib::Response& res) {
        content_type = res.get_header_value("Content-Type");
        return true;
      },
      [&](const char* data, size_t n) {
        text.append(data, n);
        return true;
      });
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_EQ(content_type, "text/event-stream");

  const auto events = ParseSse(text);
  ASSERT_GE(events.size(), 2u) << text;
  const SseEvent& last = events.back();
  EXPECT_EQ(last.event, "status");
  EXPECT_EQ(json::parse(last.data)["code"], 0);
  std::vector<json> frames;
  for (const auto& e : events)
    if (e.event.empty()) frames.push_back(json::parse(e.data));
  // duration × fps frames, clip times start + speed·k/fps, never sent early.
  ASSERT_EQ(frames.size(), static_cast<size_t>(duration * fps));
  for (size_t k = 0; k < frames.size(); ++k) {
    EXPECT_EQ(frames[k]["index"], std::to_string(k));  // uint64: a JSON string
    EXPECT_NEAR(frames[k]["time"].get<double>(), 0.25 + speed * static_cast<double>(k) / fps, 1e-9);
    EXPECT_GE(frames[k]["wallTime"].get<double>(), static_cast<double>(k) / fps - 1e-3);
    EXPECT_EQ(frames[k]["pose"]["translations"].size(), 6u);
  }
  EXPECT_EQ(frames[0]["joints"], json::array({0, 12}));
  EXPECT_EQ(frames[0]["skeleton"], "demo_walk");

  // Each frame is the pose EvaluateClip gives at that time.
  v1::EvaluateClipRequest req;
  req.set_clip("demo_walk");
  req.set_space(v1::WORLD);
  req.add_joints("Hips");
  req.add_joints("Head");
  for (const auto& f : frames) req.add_times(f["time"].get<double>());
  const auto expected = grpc.EvaluateClip(req);
  for (size_t k = 0; k < frames.size(); ++k) {
    EXPECT_EQ(Floats(frames[k]["pose"]["translations"]), Floats(expected.poses(static_cast<int>(k)).translations()));
    EXPECT_EQ(Floats(frames[k]["pose"]["rotations"]), Floats(expected.poses(static_cast<int>(k)).rotations()));
  }

  // A stream the handler refuses is a plain HTTP error.
  ExpectError(http.Get("/v1/clips/nope:stream"), 404, grpc::StatusCode::NOT_FOUND, "nope");
  ExpectError(http.Get("/v1/clips/demo_walk:stream?fps=1000"), 400, grpc::StatusCode::INVALID_ARGUMENT, "fps");
}

TEST_F(Gateway, ErrorsHaveTheirStatusAndShape) {
  ServerProcess server(data_.path(), {"--max-request-kb", "1", "--max-upload-mb", "1"});
  auto http = Http(server);
  using G = grpc::StatusCode;

  ExpectError(http.Get("/v1/clips/nope"), 404, G::NOT_FOUND, "nope");
  ExpectError(http.Get("/v2/nothing"), 404, G::NOT_FOUND, "/v2/nothing");
  // Malformed JSON says where.
  ExpectError(http.Post("/v1/clips/demo_walk:evaluate", "{\"times\": [0.5],\n \"space\": WORLD}", "application/json"),
              400, G::INVALID_ARGUMENT, "line 2, column");
  // A wrong type names the field.
  ExpectError(http.Post("/v1/clips/demo_walk:evaluate", R"({"times":[0.5,"soon"]})", "application/json"), 400,
              G::INVALID_ARGUMENT, "times[1]");
  ExpectError(http.Post("/v1/clips/demo_walk:evaluate", R"({"times":[0.5],"space":"SIDEWAYS"})", "application/json"),
              400, G::INVALID_ARGUMENT, "space");
  ExpectError(http.Post("/v1/clips/demo_walk:evaluate", R"({"times":[0.5],"tiems":[1]})", "application/json"), 400,
              G::INVALID_ARGUMENT, "tiems");
  ExpectError(http.Get("/v1/clips/demo_walk:stream?fps=fast"), 400, G::INVALID_ARGUMENT, "'fps'");
  ExpectError(http.Get("/v1/clips/demo_walk:stream?fsp=30"), 400, G::INVALID_ARGUMENT, "'fsp'");
  ExpectError(http.Get("/v1/clips/demo_walk:stream?fps=30&fps=60"), 400, G::INVALID_ARGUMENT, "takes one value");
  // Validation stays with the gRPC handler; the gateway passes its word on.
  ExpectError(http.Post("/v1/clips/demo_walk:evaluate", R"({"times":[0.5,-1]})", "application/json"), 400,
              G::INVALID_ARGUMENT, "times[1]: must not be negative");
  ExpectError(http.Post("/v1/clips/demo_walk:evaluate", R"({"times":[0.5],"joints":["Tail"]})", "application/json"),
              404, G::NOT_FOUND, "joints[0]");
  // The deadline comes from grpc-timeout: an endless stream ends when it passes.
  const auto timed = http.Get("/v1/clips/demo_walk:stream?fps=10&loop=true", {{"grpc-timeout", "300m"}});
  ASSERT_EQ(timed->status, 200);
  const auto timed_events = ParseSse(timed->body);
  ASSERT_FALSE(timed_events.empty());
  EXPECT_EQ(timed_events.back().event, "status");
  EXPECT_EQ(json::parse(timed_events.back().data)["code"], static_cast<int>(G::DEADLINE_EXCEEDED));
  ExpectError(http.Post("/v1/clips/demo_walk:evaluate", httplib::Headers{{"grpc-timeout", "soon"}},
                        R"({"times":[0.5]})", "application/json"),
              400, G::INVALID_ARGUMENT, "grpc-timeout");

  // Wrong methods: 405 with Allow.
  const auto put = http.Put("/v1/clips/demo_walk", "{}", "application/json");
  ExpectError(put, 405, G::UNIMPLEMENTED, "PUT");
  EXPECT_EQ(put->get_header_value("Allow"), "DELETE, GET, HEAD, OPTIONS");
  const auto get = http.Get("/v1/clips/demo_walk:evaluate");
  ExpectError(get, 405, G::UNIMPLEMENTED, "GET");
  EXPECT_EQ(get->get_header_value("Allow"), "POST, OPTIONS");

  // Bodies over the limits: 413 (JSON: --max-request-kb; raw import: --max-upload-mb).
  const std::string padding(2000, ' ');
  ExpectError(http.Post("/v1/clips/demo_walk:evaluate", R"({"times":[0.5]})" + padding, "application/json"), 413,
              G::RESOURCE_EXHAUSTED, "--max-request-kb");
  ExpectError(
      http.Post("/v1/assets:import?filename=big.bvh", std::string((1 << 20) + 1, 'x'), "application/octet-stream"), 413,
      G::RESOURCE_EXHAUSTED, "--max-upload-mb");
  // The server is fine afterwards.
  EXPECT_EQ(http.Get("/v1/clips")->status, 200);
  // A request id comes back.
  const auto with_id = http.Get("/v1/clips", httplib::Headers{{"x-request-id", "abc-123"}});
  EXPECT_EQ(with_id->get_header_value("x-request-id"), "abc-123");
}

TEST_F(Gateway, CorsForConfiguredOriginsOnly) {
  ::setenv("ARMATURE_CORS_ORIGIN", "http://env.example,http://other.example", 1);
  ServerProcess server(data_.path(), {"--cors-origin", "http://app.example"});
  ::unsetenv("ARMATURE_CORS_ORIGIN");
  auto http = Http(server);

  // The flag wins over the environment (CLI11); the env form is checked below.
  const auto preflight =
      http.Options("/v1/clips/demo_walk:evaluate", {{"Origin", "http://app.example"},
                                                    {"Access-Control-Request-Method", "POST"},
                                                    {"Access-Control-Request-Headers", "content-type"}});
  ASSERT_TRUE(preflight);
  EXPECT_EQ(preflight->status, 204);
  EXPECT_EQ(preflight->get_header_value("Access-Control-Allow-Origin"), "http://app.example");
  EXPECT_EQ(preflight->get_header_value("Access-Control-Allow-Methods"), "POST, OPTIONS");
  EXPECT_NE(preflight->get_header_value("Access-Control-Allow-Headers").find("content-type"), std::string::npos);
  EXPECT_EQ(preflight->get_header_value("Vary"), "Origin");

  const auto get = http.Get("/v1/clips", {{"Origin", "http://app.example"}});
  EXPECT_EQ(get->status, 200);
  EXPECT_EQ(get->get_header_value("Access-Control-Allow-Origin"), "http://app.example");

  const auto foreign =
      http.Options("/v1/clips", {{"Origin", "http://evil.example"}, {"Access-Control-Request-Method", "GET"}});
  ExpectError(foreign, 403, grpc::StatusCode::PERMISSION_DENIED, "evil.example");
  EXPECT_FALSE(foreign->has_header("Access-Control-Allow-Origin"));
  EXPECT_FALSE(http.Get("/v1/clips", {{"Origin", "http://evil.example"}})->has_header("Access-Control-Allow-Origin"));

  // A plain OPTIONS lists the methods.
  const auto options = http.Options("/v1/clips/demo_walk");
  EXPECT_EQ(options->status, 204);
  EXPECT_EQ(options->get_header_value("Allow"), "DELETE, GET, HEAD, OPTIONS");

  // ARMATURE_CORS_ORIGIN, comma-separated.
  ::setenv("ARMATURE_CORS_ORIGIN", "http://env.example,http://other.example", 1);
  ServerProcess from_env(data_.path());
  ::unsetenv("ARMATURE_CORS_ORIGIN");
  auto http_env = Http(from_env);
  for (const std::string origin : {"http://env.example", "http://other.example"}) {
    const auto r = http_env.Options("/v1/clips", {{"Origin", origin}, {"Access-Control-Request-Method", "GET"}});
    EXPECT_EQ(r->status, 204) << origin;
    EXPECT_EQ(r->get_header_value("Access-Control-Allow-Origin"), origin);
  }
}

TEST_F(Gateway, SlowAndVanishedStreamClientsBlockNobody) {
  // 16 HTTP threads leave 12 stream slots and 4 threads for everything else.
  ServerProcess server(data_.path(), {"--http-threads", "16"});
  const std::string request =
      "GET /v1/clips/demo_walk:stream?fps=60&loop=true HTTP/1.1\r\nHost: localhost\r\nAccept: "
      "text/event-stream\r\n\r\n";
  const int slots = 12;
  std::vector<std::unique_ptr<RawClient>> clients;
  for (int i = 0; i < slots; ++i) {
    clients.push_back(std::make_unique<RawClient>(server.http_port()));
    clients.back()->Send(request);
    const std::string head = clients.back()->ReadUntil("data: ");
    ASSERT_NE(head.find("200 OK"), std::string::npos) << head;
  }
  auto http = Http(server);
  // Every slot is taken: one stream more is refused at once...
  ExpectError(http.Get("/v1/clips/demo_walk:stream?fps=10&duration=0.2"), 429, grpc::StatusCode::RESOURCE_EXHAUSTED,
              "too many open streams");
  // ...while ordinary requests go on, though none of the streams reads.
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(http.Get("/v1/clips")->status, 200);
    EXPECT_EQ(http.Post("/v1/clips/demo_walk:evaluate", R"({"times":[0.5]})", "application/json")->status, 200);
  }

  // The clients vanish: their calls are cancelled and every slot comes back.
  // Each slot is freed when its handler notices the closed socket, one by one
  // and at no fixed time on a loaded machine: wait until a full batch of
  // `slots` concurrent streams is served, which is what is asserted.
  for (auto& c : clients) c->Close();
  std::vector<int> statuses;
  const bool all_served = WaitFor(
      [&] {
        std::vector<std::future<int>> streams;
        for (int i = 0; i < slots; ++i)
          streams.push_back(std::async(std::launch::async, [&server] {
            auto h = Http(server);
            const auto r = h.Get("/v1/clips/demo_walk:stream?fps=10&duration=0.5");
            return r ? r->status : -1;
          }));
        statuses.clear();
        for (auto& s : streams) statuses.push_back(s.get());
        return std::count(statuses.begin(), statuses.end(), 200) == slots;
      },
      60);
  EXPECT_TRUE(all_served) << "stream slots were not all freed when their clients went away; last batch: "
                          << ::testing::PrintToString(statuses);
}

TEST_F(Gateway, ShutdownGivesRestCallsTheGracePeriodThenCancelsStreams) {
  // A grace period long enough that the checks below run inside it on a loaded machine.
  ServerProcess server(data_.path(), {"--shutdown-grace", "4"});
  std::atomic<int> frames{0};
  std::atomic<int> frames_at_signal{-1};
  std::string text;
  std::thread stream([&] {
    auto http = Http(server);
    http.Get("/v1/clips/demo_walk:stream?fps=10&loop=true", [&](const char* data, size_t n) {
      const std::string chunk(data, n);
      for (size_t at = chunk.find("\"index\""); at != std::string::npos; at = chunk.find("\"index\"", at + 1)) ++frames;
      text += chunk;  // read by the main thread only after join
      return true;
    });
  });
  ASSERT_TRUE(WaitFor([&] { return frames >= 3; }, 30)) << "the stream did not start";
  frames_at_signal = frames.load();
  ASSERT_EQ(::kill(server.pid(), SIGTERM), 0);
  auto http = Http(server);
  // Not ready any more, and new REST calls are refused...
  ASSERT_TRUE(WaitFor(
      [&] {
        const auto r = http.Get("/readyz");
        return r && r->status == 503;
      },
      3))
      << "/readyz did not turn 503 within the grace period";
  ExpectError(http.Get("/v1/clips"), 503, grpc::StatusCode::UNAVAILABLE, "shutting down");
  // ...while the open stream plays on through the grace period, then ends cancelled.
  EXPECT_EQ(server.Stop(SIGTERM, 30), 0);
  stream.join();
  EXPECT_GT(frames.load(), frames_at_signal.load() + 2) << "the stream was cut at once";
  const auto events = ParseSse(text);
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().event, "status");
  EXPECT_EQ(json::parse(events.back().data)["code"], static_cast<int>(grpc::StatusCode::CANCELLED));
}

TEST_F(Gateway, OpenApiIsGeneratedFromTheDescriptors) {
  ServerProcess server(data_.path());
  auto http = Http(server);
  const auto r = http.Get("/openapi.json");
  ASSERT_EQ(r->status, 200);
  const json doc = Body(r);
  EXPECT_EQ(doc["openapi"], "3.0.3");
  const json& evaluate = doc["paths"]["/v1/clips/{clip}:evaluate"]["post"];
  EXPECT_EQ(evaluate["operationId"], "PoseService_EvaluateClip");
  EXPECT_EQ(evaluate["parameters"][0]["name"], "clip");
  EXPECT_EQ(evaluate["parameters"][0]["in"], "path");
  EXPECT_EQ(evaluate["requestBody"]["content"]["application/json"]["schema"]["$ref"],
            "#/components/schemas/armature.v1.EvaluateClipRequest");
  // Query parameters of a GET, lowerCamelCase; a server stream is an event stream.
  const json& stream = doc["paths"]["/v1/clips/{clip}:stream"]["get"];
  std::set<std::string> names;
  for (const auto& p : stream["parameters"]) names.insert(p["name"].get<std::string>());
  EXPECT_TRUE(names.count("fps") && names.count("startTime") && names.count("joints")) << stream.dump();
  EXPECT_TRUE(stream["responses"]["200"]["content"].contains("text/event-stream"));
  // The import takes the raw file.
  EXPECT_TRUE(doc["paths"]["/v1/assets:import"]["post"]["requestBody"]["content"].contains("application/octet-stream"));
  EXPECT_TRUE(doc["paths"]["/v1/clips/{name}"]["delete"].is_object());
  const json& schemas = doc["components"]["schemas"];
  ASSERT_TRUE(schemas.contains("armature.v1.Space"));
  EXPECT_EQ(schemas["armature.v1.Space"]["enum"], json::array({"SPACE_UNSPECIFIED", "LOCAL", "WORLD"}));
  ASSERT_TRUE(schemas.contains("armature.v1.EvaluateClipRequest"));
  EXPECT_EQ(schemas["armature.v1.EvaluateClipRequest"]["properties"]["times"]["items"]["type"], "number");
  ASSERT_TRUE(schemas.contains("armature.v1.PoseFrame"));
  EXPECT_EQ(schemas["armature.v1.PoseFrame"]["properties"]["wallTime"]["type"], "number");
  EXPECT_EQ(schemas["armature.v1.PoseFrame"]["properties"]["index"]["type"], "string");  // uint64
  // Every annotated RPC is there.
  int operations = 0;
  for (const auto& [path, methods] : doc["paths"].items()) operations += static_cast<int>(methods.size());
  EXPECT_EQ(operations, 32);  // 15 asset and pose routes (EvaluateMotion, PlaybackSession among them), Deform +
                              // DeformSession, SolveIk + IkSession, MeshService's 10 (SkinCharacter, GetMaterial,
                              // GetMaterialImage), AuthoringService's 2 (RetargetClip, CreateClip), CrowdSession
  EXPECT_TRUE(doc["paths"]["/v1/crowds:session"]["post"].is_object());
  EXPECT_TRUE(doc["paths"]["/v1/clips/{clip}:retarget"]["post"].is_object());
  EXPECT_TRUE(doc["paths"]["/v1/meshes/{mesh}:deform"]["post"].is_object());
  EXPECT_TRUE(doc["paths"]["/v1/skeletons/{skeleton}:createClip"]["post"].is_object());
}

}  // namespace
}  // namespace armature::testing
