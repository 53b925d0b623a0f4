// The gateway without armature-server: the transcoder over a service the
// test defines at run time (descriptors built here, served by a generic gRPC
// echo handler), which covers the RPC kinds the Armature API does not have
// yet, bidirectional streaming among them.
#include <thread>

#include <google/protobuf/descriptor.pb.h>
#include <google/protobuf/dynamic_message.h>
#include <grpcpp/generic/async_generic_service.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "../../../common/sse_events.h"
#include "google/api/annotations.pb.h"
#include "server/host/gateway/gateway.h"

namespace armature::server::gateway {
namespace {

namespace pb = google::protobuf;
using nlohmann::json;

// test.v1.EchoService: Chat (bidi), Collect (client stream), Say (unary),
// each bound by a (google.api.http) rule set here.
class DynamicService {
 public:
  DynamicService() {
    pb::FileDescriptorProto file;
    file.set_name("test/echo.proto");
    file.set_package("test.v1");
    file.set_syntax("proto3");
    auto* msg = file.add_message_type();
    msg->set_name("EchoMessage");
    AddField(msg, "text", 1, pb::FieldDescriptorProto::TYPE_STRING, false);
    AddField(msg, "count", 2, pb::FieldDescriptorProto::TYPE_INT32, false);
    AddField(msg, "tags", 3, pb::FieldDescriptorProto::TYPE_STRING, true);
    auto* service = file.add_service();
    service->set_name("EchoService");
    AddMethod(service, "Chat", true, true, Rule("post", "/v1/echo:chat", "*"));
    AddMethod(service, "Collect", true, false, Rule("post", "/v1/echo:collect", "*"));
    AddMethod(service, "Say", false, false, Rule("get", "/v1/echo/{text}", ""));
    file_ = pool_.BuildFile(file);
  }

  const pb::ServiceDescriptor* service() const { return file_ ? file_->service(0) : nullptr; }
  pb::MessageFactory* factory() { return &factory_; }

  static google::api::HttpRule Rule(const std::string& method, const std::string& path, const std::string& body) {
    google::api::HttpRule rule;
    if (method == "get") rule.set_get(path);
    if (method == "post") rule.set_post(path);
    rule.set_body(body);
    return rule;
  }

 private:
  static void AddField(pb::DescriptorProto* msg, const std::string& name, int number,
                       pb::FieldDescriptorProto::Type type, bool repeated) {
    auto* f = msg->add_field();
    f->set_name(name);
    f->set_number(number);
    f->set_type(type);
    f->set_label(repeated ? pb::FieldDescriptorProto::LABEL_REPEATED : pb::FieldDescriptorProto::LABEL_OPTIONAL);
  }
  static void AddMethod(pb::ServiceDescriptorProto* service, const std::string& name, bool client_streaming,
                        bool server_streaming, const google::api::HttpRule& rule) {
    auto* m = service->add_method();
    m->set_name(name);
    m->set_input_type(".test.v1.EchoMessage");
    m->set_output_type(".test.v1.EchoMessage");
    m->set_client_streaming(client_streaming);
    m->set_server_streaming(server_streaming);
    *m->mutable_options()->MutableExtension(google::api::http) = rule;
  }

  pb::DescriptorPool pool_;
  const pb::FileDescriptor* file_ = nullptr;
  pb::DynamicMessageFactory factory_{&pool_};
};

// Answers every method by sending each request back, then OK; refuses the
// token "Bearer wrong" as an auth interceptor would, quoting the request id.
class EchoService final : public grpc::CallbackGenericService {
  grpc::ServerGenericBidiReactor* CreateReactor(grpc::GenericCallbackServerContext* context) override {
    class Reactor final : public grpc::ServerGenericBidiReactor {
     public:
      explicit Reactor(const grpc::GenericCallbackServerContext* context) {
        const auto& md = context->client_metadata();
        const auto value = [&](const char* key) {
          auto it = md.find(key);
          return it == md.end() ? std::string() : std::string(it->second.data(), it->second.size());
        };
        if (value("authorization") == "Bearer wrong") {
          Finish(grpc::Status(grpc::StatusCode::UNAUTHENTICATED, "bad token (request " + value("x-request-id") + ")"));
          return;
        }
        StartRead(&buffer_);
      }
      void OnReadDone(bool ok) override {
        if (!ok) return Finish(grpc::Status::OK);
        StartWrite(&buffer_);
      }
      void OnWriteDone(bool ok) override {
        if (!ok) return Finish(grpc::Status::CANCELLED);
        StartRead(&buffer_);
      }
      void OnDone() override { delete this; }

     private:
      grpc::ByteBuffer buffer_;
    };
    return new Reactor(context);
  }
};

class DynamicGateway : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_NE(types_.service(), nullptr);
    grpc::ServerBuilder builder;
    builder.RegisterCallbackGenericService(&echo_);
    grpc_ = builder.BuildAndStart();
    auto gw = Gateway::Create({types_.service()}, types_.factory(), grpc_->InProcessChannel(grpc::ChannelArguments()),
                              GatewayOptions());
    ASSERT_TRUE(gw.ok()) << gw.status().message();
    gateway_ = std::move(*gw);
    gateway_->Register(http_);
    port_ = http_.bind_to_any_port("127.0.0.1");
    thread_ = std::thread([this] { http_.listen_after_bind(); });
  }
  void TearDown() override {
    http_.stop();
    if (thread_.joinable()) thread_.join();
    if (grpc_) grpc_->Shutdown();
  }
  httplib::Client Client() { return httplib::Client("127.0.0.1", port_); }

  DynamicService types_;
  EchoService echo_;
  std::unique_ptr<grpc::Server> grpc_;
  std::unique_ptr<Gateway> gateway_;
  httplib::Server http_;
  int port_ = 0;
  std::thread thread_;
};

// The data of the message events, and of the final status event into `status`.
std::vector<std::string> DataEvents(const std::string& sse, std::string* status) {
  std::vector<std::string> data;
  for (const auto& e : testing::ParseSse(sse)) {
    if (e.event == "status")
      *status = e.data;
    else
      data.push_back(e.data);
  }
  return data;
}

TEST_F(DynamicGateway, BidiStreamTakesNdjsonAndAnswersWithServerSentEvents) {
  auto http = Client();
  const auto r = http.Post("/v1/echo:chat", "{\"text\":\"a\",\"count\":1}\n\n{\"text\":\"b\",\"tags\":[\"x\"]}\n",
                           "application/x-ndjson");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(r->get_header_value("Content-Type"), "text/event-stream");
  std::string status;
  const auto events = DataEvents(r->body, &status);
  ASSERT_EQ(events.size(), 2u) << r->body;
  EXPECT_EQ(json::parse(events[0]), json::parse(R"({"text":"a","count":1,"tags":[]})"));
  EXPECT_EQ(json::parse(events[1]), json::parse(R"({"text":"b","count":0,"tags":["x"]})"));
  EXPECT_EQ(json::parse(status)["code"], 0);

  // One JSON body is one message; a bad line is a 400 naming the line.
  const auto one = http.Post("/v1/echo:chat", R"({"text":"solo"})", "application/json");
  ASSERT_EQ(one->status, 200);
  EXPECT_EQ(DataEvents(one->body, &status).size(), 1u);
  const auto bad = http.Post("/v1/echo:chat", "{\"text\":\"a\"}\n{\"count\":\"many\"}\n", "application/x-ndjson");
  EXPECT_EQ(bad->status, 400);
  EXPECT_NE(bad->body.find("request body line 2"), std::string::npos) << bad->body;
}

TEST_F(DynamicGateway, ClientStreamAndUnaryThroughTheSameTranscoder) {
  auto http = Client();
  // A client stream answered once: the echo sends each message back, so a
  // unary-response method getting two answers is the server's error, shown as 500.
  const auto collect = http.Post("/v1/echo:collect", "{\"text\":\"only\"}\n", "application/x-ndjson");
  ASSERT_EQ(collect->status, 200) << collect->body;
  EXPECT_EQ(json::parse(collect->body)["text"], "only");
  const auto two = http.Post("/v1/echo:collect", "{\"text\":\"a\"}\n{\"text\":\"b\"}\n", "application/x-ndjson");
  EXPECT_EQ(two->status, 500) << two->body;

  const auto say = http.Get("/v1/echo/hi%20there?count=3&tags=x&tags=y");
  ASSERT_EQ(say->status, 200) << say->body;
  EXPECT_EQ(json::parse(say->body), json::parse(R"({"text":"hi there","count":3,"tags":["x","y"]})"));
  EXPECT_EQ(http.Get("/v1/echo/hi?count=x")->status, 400);
  EXPECT_EQ(http.Get("/v1/echo/hi?text=x")->status, 400);  // the path sets it

  // authorization and x-request-id reach the handler as metadata.
  const auto denied = http.Get("/v1/echo/hi", {{"Authorization", "Bearer wrong"}, {"X-Request-Id", "r-42"}});
  EXPECT_EQ(denied->status, 401);
  EXPECT_EQ(json::parse(denied->body)["code"], 16);
  EXPECT_EQ(json::parse(denied->body)["message"], "bad token (request r-42)");
  EXPECT_EQ(http.Get("/v1/echo/hi", {{"Authorization", "Bearer right"}})->status, 200);
}

TEST(GatewayCreate, RejectsRulesThatDoNotFitTheMessages) {
  pb::FileDescriptorProto file;
  file.set_name("test/bad.proto");
  file.set_package("test.bad");
  file.set_syntax("proto3");
  auto* msg = file.add_message_type();
  msg->set_name("M");
  auto* f = msg->add_field();
  f->set_name("name");
  f->set_number(1);
  f->set_type(pb::FieldDescriptorProto::TYPE_STRING);
  f->set_label(pb::FieldDescriptorProto::LABEL_OPTIONAL);
  auto* m = file.add_service();
  m->set_name("S");
  auto* method = m->add_method();
  method->set_name("Get");
  method->set_input_type(".test.bad.M");
  method->set_output_type(".test.bad.M");
  *method->mutable_options()->MutableExtension(google::api::http) = DynamicService::Rule("get", "/v1/{nope}", "");
  pb::DescriptorPool pool;
  const pb::FileDescriptor* built = pool.BuildFile(file);
  ASSERT_NE(built, nullptr);
  pb::DynamicMessageFactory factory(&pool);
  // Never connected: Create only compiles the rules.
  auto channel = grpc::CreateChannel("localhost:1", grpc::InsecureChannelCredentials());
  auto gw = Gateway::Create({built->service(0)}, &factory, channel, {});
  ASSERT_FALSE(gw.ok());
  EXPECT_NE(gw.status().message().find("test.bad.S.Get"), std::string::npos) << gw.status().message();
  EXPECT_NE(gw.status().message().find("no field 'nope'"), std::string::npos) << gw.status().message();
}

}  // namespace
}  // namespace armature::server::gateway
