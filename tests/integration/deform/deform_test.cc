// DeformService end to end: a grid with a bump the test writes as OBJ,
// imported, deformed through gRPC, the REST gateway and a drag session, and
// compared with the SciPy reference (tests/reference/laplacian_reference.py,
// a KKT solve with SuperLU: a different route from the engine's).
#include <csignal>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <string>
#include <vector>

// The test fixtures (Eigen) before httplib.h, whose system headers define a
// macro that breaks Eigen's product kernels.
#include "engine/testing/deformation_test_util.h"
#include "engine/testing/scipy_reference.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"
#include "armature/v1/deform.grpc.pb.h"
#include "support/client_helpers.h"
#include "support/deform_grid.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {
using nlohmann::json;

class Deform : public ::testing::Test {
 protected:
  void SetUp() override {
    grid_ = MakeGrid(17);
    server_.emplace(data_.path(), std::vector<std::string>{"--no-demo", "--max-sessions-per-client", "3"});
    client_.emplace(OptionsFor(*server_));
    const auto imported = client_->Import({"bump.obj", grid_.obj}, "bump");
    ASSERT_EQ(imported.asset().meshes_size(), 1);
    mesh_ = imported.asset().meshes(0).name();
    ASSERT_EQ(imported.asset().meshes(0).vertex_count(), grid_.n * grid_.n);
    stub_ = v1::DeformService::NewStub(client_->channel());
  }

  v1::DeformResponse Call(const v1::DeformRequest& r) { return client_->Deform(r); }

  TempDir data_;
  Grid grid_;
  std::optional<ServerProcess> server_;
  std::optional<client::Client> client_;
  std::string mesh_;
  std::unique_ptr<v1::DeformService::Stub> stub_;
};

TEST_F(Deform, UnaryMatchesScipyForBothWeightings) {
  if (!fixtures::ScipyAvailable())
    GTEST_SKIP() << "/usr/bin/python3 with scipy is not installed (scripts/setup.sh test)";
  const Edit e = BumpEdit(grid_);
  for (auto [weights, name] : {std::pair{v1::UNIFORM, "uniform"}, std::pair{v1::COTANGENT, "cotangent"}}) {
    const TempDir scratch;
    const auto rows = fixtures::LaplacianScipyReference(grid_.mesh, name, e.fixed, {}, e.handles,
                                                        fixtures::AsRows(e.targets), scratch.path());
    ASSERT_TRUE(rows.has_value()) << "the SciPy reference script failed";
    const std::vector<double> reference = fixtures::Interleave(*rows);
    const v1::DeformResponse r = Call(RequestFor(mesh_, e, weights));
    EXPECT_EQ(r.mesh(), mesh_);
    ASSERT_EQ(static_cast<size_t>(r.positions_size()), reference.size());
    double worst = 0, moved = 0;
    for (size_t i = 0; i < reference.size(); ++i) {
      worst = std::max(worst, std::abs(double{r.positions(static_cast<int>(i))} - reference[i]));
      moved = std::max(moved, std::abs(reference[i] - double{grid_.positions[i]}));
    }
    EXPECT_LT(worst, 1e-6) << name;
    std::printf("%s weights: largest |server - SciPy| = %.3g over %zu coordinates (largest move %.3g)\n", name, worst,
                reference.size(), moved);
    EXPECT_GT(moved, 0.1) << name << ": the edit must move the surface for the comparison to mean anything";
    for (int a = 0; a < 3; ++a)
      EXPECT_EQ(r.positions(static_cast<int>(3 * e.handles[0]) + a), static_cast<float>(e.targets[a])) << name;
  }
}

TEST_F(Deform, RestGatewayGivesTheGrpcNumbers) {
  const Edit e = BumpEdit(grid_);
  const v1::DeformResponse grpc_answer = Call(RequestFor(mesh_, e, v1::COTANGENT));
  json body = {{"weights", "COTANGENT"}, {"fixed", e.fixed}};
  body["handles"] = json::array({{{"index", e.handles[0]}, {"position", e.targets}}});
  httplib::Client http("127.0.0.1", server_->http_port());
  const auto r = http.Post("/v1/meshes/" + mesh_ + ":deform", body.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json j = json::parse(r->body);
  ASSERT_EQ(j["positions"].size(), static_cast<size_t>(grpc_answer.positions_size()));
  for (int i = 0; i < grpc_answer.positions_size(); ++i)
    EXPECT_EQ(j["positions"][static_cast<size_t>(i)].get<float>(), grpc_answer.positions(i)) << i;
  const auto bad = http.Post("/v1/meshes/" + mesh_ + ":deform", R"({"handles":[{"index":100000,"position":[0,0,0]}]})",
                             "application/json");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400) << bad->body;
  EXPECT_NE(bad->body.find("out of range"), std::string::npos) << bad->body;
}

TEST_F(Deform, BadInputIsInvalidArgumentNamingTheProblem) {
  const Edit e = BumpEdit(grid_);
  auto expect = [&](const v1::DeformRequest& r, const std::string& fragment) {
    const grpc::Status status = StatusOf([&] { Call(r); });
    const std::string& message = status.error_message();
    EXPECT_EQ(status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << "want \"" << fragment << "\" in: " << message;
  };
  v1::DeformRequest out_of_range = RequestFor(mesh_, e, v1::UNIFORM);
  out_of_range.mutable_handles(0)->set_index(5000);
  expect(out_of_range, "5000");
  expect(out_of_range, "out of range");
  v1::DeformRequest also_fixed = RequestFor(mesh_, e, v1::UNIFORM);
  also_fixed.mutable_handles(0)->set_index(e.fixed[2]);
  expect(also_fixed, "fixed");
  v1::DeformRequest nan = RequestFor(mesh_, e, v1::UNIFORM);
  nan.mutable_handles(0)->set_position(1, std::numeric_limits<double>::quiet_NaN());
  expect(nan, "non-finite");
  v1::DeformRequest two_values = RequestFor(mesh_, e, v1::UNIFORM);
  two_values.mutable_handles(0)->mutable_position()->RemoveLast();
  expect(two_values, "handles[0].position");

  // Two separate triangles, only the first constrained: the second is singular.
  client_->Import({"two.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 0 0\nv 6 0 0\nv 5 1 0\nf 1 2 3\nf 4 5 6\n"}, "two");
  v1::DeformRequest singular;
  singular.set_mesh("two");
  singular.add_fixed(0);
  auto* h = singular.add_handles();
  h->set_index(1);
  for (double x : {1.0, 0.5, 0.0}) h->add_position(x);
  expect(singular, "component");

  v1::DeformRequest unknown = RequestFor("nope", e, v1::UNIFORM);
  EXPECT_EQ(CodeOf([&] { Call(unknown); }), grpc::StatusCode::NOT_FOUND);
}

// Opens a session and returns the answer to its start message.
using SessionStream = grpc::ClientReaderWriter<v1::DeformSessionRequest, v1::DeformResponse>;
std::unique_ptr<SessionStream> OpenSession(v1::DeformService::Stub& stub, grpc::ClientContext& context,
                                           const std::string& mesh, const Edit& e, v1::DeformMethod method,
                                           v1::DeformResponse* first) {
  auto stream = stub.DeformSession(&context);
  v1::DeformSessionRequest start;
  auto* s = start.mutable_start();
  s->mutable_setup()->set_mesh(mesh);
  s->mutable_setup()->set_method(method);
  for (uint32_t v : e.fixed) s->mutable_setup()->add_fixed(v);
  for (uint32_t v : e.handles) s->add_handle_indices(v);
  stream->Write(start);
  if (!stream->Read(first)) first->Clear();
  return stream;
}

TEST_F(Deform, SessionAnswersEveryMoveWithHandlesOnTarget) {
  const Edit e = BumpEdit(grid_);
  for (v1::DeformMethod method : {v1::LAPLACIAN, v1::ARAP}) {
    grpc::ClientContext context;
    v1::DeformResponse first;
    auto stream = OpenSession(*stub_, context, mesh_, e, method, &first);
    ASSERT_EQ(first.positions_size(), 3 * grid_.n * grid_.n);
    for (int i = 0; i < first.positions_size(); ++i) ASSERT_NEAR(first.positions(i), grid_.positions[i], 1e-6) << i;
    const uint32_t h = e.handles[0];
    for (int k = 1; k <= 60; ++k) {
      const double t = k / 60.0;
      const double target[3] = {grid_.positions[3 * h] + 0.2 * t, grid_.positions[3 * h + 1],
                                grid_.positions[3 * h + 2] + 0.5 * std::sin(3 * t)};
      v1::DeformSessionRequest move;
      for (double x : target) move.mutable_move()->add_positions(x);
      ASSERT_TRUE(stream->Write(move));
      v1::DeformResponse r;
      ASSERT_TRUE(stream->Read(&r)) << "move " << k;
      EXPECT_EQ(r.index(), static_cast<uint64_t>(k));
      for (int a = 0; a < 3; ++a)
        EXPECT_EQ(r.positions(static_cast<int>(3 * h) + a), static_cast<float>(target[a])) << k;
      for (uint32_t f : e.fixed)
        for (int a = 0; a < 3; ++a) EXPECT_EQ(r.positions(static_cast<int>(3 * f) + a), grid_.positions[3 * f + a]);
      if (method == v1::LAPLACIAN && k == 60) {  // the session's answer is the unary answer for the same targets
        Edit last = e;
        last.targets.assign(target, target + 3);
        const v1::DeformResponse unary = Call(RequestFor(mesh_, last, v1::UNIFORM));
        for (int i = 0; i < unary.positions_size(); ++i) EXPECT_NEAR(r.positions(i), unary.positions(i), 1e-6) << i;
      }
    }
    ASSERT_TRUE(stream->WritesDone());
    EXPECT_TRUE(stream->Finish().ok());
  }
}

TEST_F(Deform, SessionBadMoveEndsItNamingTheField) {
  const Edit e = BumpEdit(grid_);
  grpc::ClientContext context;
  v1::DeformResponse first;
  auto stream = OpenSession(*stub_, context, mesh_, e, v1::LAPLACIAN, &first);
  ASSERT_GT(first.positions_size(), 0);
  v1::DeformSessionRequest move;
  move.mutable_move()->add_positions(1);  // one value for one handle: needs 3
  stream->Write(move);
  v1::DeformResponse r;
  EXPECT_FALSE(stream->Read(&r));
  const grpc::Status st = stream->Finish();
  EXPECT_EQ(st.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(st.error_message().find("move[1].positions"), std::string::npos) << st.error_message();
}

// The client library's session: the same answers as the raw stream, errors as ClientError.
TEST_F(Deform, ClientSessionMovesLikeTheStreamAndThrowsOnBadMoves) {
  const Edit e = BumpEdit(grid_);
  v1::DeformSessionStart start;
  start.mutable_setup()->set_mesh(mesh_);
  start.mutable_setup()->set_method(v1::ARAP);
  for (uint32_t v : e.fixed) start.mutable_setup()->add_fixed(v);
  for (uint32_t v : e.handles) start.add_handle_indices(v);
  auto session = client_->OpenDeformSession(start);
  ASSERT_EQ(session->last().positions_size(), 3 * grid_.n * grid_.n);
  for (int i = 0; i < session->last().positions_size(); ++i)
    ASSERT_NEAR(session->last().positions(i), grid_.positions[i], 1e-6) << i;  // the rest shape
  grpc::ClientContext context;
  v1::DeformResponse first;
  auto stream = OpenSession(*stub_, context, mesh_, e, v1::ARAP, &first);
  for (int k = 1; k <= 3; ++k) {
    const std::vector<double> target = {e.targets[0] * k / 3, e.targets[1], e.targets[2] * k / 3};
    const v1::DeformResponse& mine = session->Move(target);
    v1::DeformSessionRequest move;
    move.mutable_move()->mutable_positions()->Add(target.begin(), target.end());
    v1::DeformResponse theirs;
    ASSERT_TRUE(stream->Write(move) && stream->Read(&theirs));
    EXPECT_EQ(mine.index(), static_cast<uint64_t>(k));
    EXPECT_GT(mine.iterations(), 0);
    ASSERT_EQ(mine.positions_size(), theirs.positions_size());
    for (int i = 0; i < mine.positions_size(); ++i) ASSERT_EQ(mine.positions(i), theirs.positions(i)) << k << ": " << i;
    for (int a = 0; a < 3; ++a)
      EXPECT_EQ(mine.positions(static_cast<int>(3 * e.handles[0]) + a), static_cast<float>(target[a]));
  }
  stream->WritesDone();
  EXPECT_TRUE(stream->Finish().ok());
  const std::vector<double> two_values = {1, 2};
  EXPECT_EQ(CodeOf([&] { session->Move(two_values); }), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(MessageOf([&] { session->Move(two_values); }).find("is closed"), std::string::npos);
  EXPECT_EQ(CodeOf([&] { session->Move(two_values); }), grpc::StatusCode::FAILED_PRECONDITION);
  session->Close();  // already ended: nothing to do
  auto bad = [&] {
    v1::DeformSessionStart unknown = start;
    unknown.mutable_setup()->set_mesh("nope");
    client_->OpenDeformSession(unknown);
  };
  EXPECT_EQ(CodeOf(bad), grpc::StatusCode::NOT_FOUND);
}

TEST_F(Deform, SessionsPerClientAreLimitedAndFreedWhenTheyEnd) {
  const Edit e = BumpEdit(grid_);
  std::vector<std::unique_ptr<grpc::ClientContext>> contexts;
  std::vector<std::unique_ptr<SessionStream>> open;
  for (int i = 0; i < 3; ++i) {  // --max-sessions-per-client 3
    contexts.push_back(std::make_unique<grpc::ClientContext>());
    v1::DeformResponse first;
    open.push_back(OpenSession(*stub_, *contexts.back(), mesh_, e, v1::LAPLACIAN, &first));
    ASSERT_GT(first.positions_size(), 0) << "session " << i;
  }
  {
    grpc::ClientContext context;
    v1::DeformResponse first;
    auto refused = OpenSession(*stub_, context, mesh_, e, v1::LAPLACIAN, &first);
    EXPECT_EQ(first.positions_size(), 0);
    const grpc::Status st = refused->Finish();
    EXPECT_EQ(st.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
    EXPECT_NE(st.error_message().find("--max-sessions-per-client (3)"), std::string::npos) << st.error_message();
  }
  open[0]->WritesDone();
  EXPECT_TRUE(open[0]->Finish().ok());
  grpc::ClientContext context;
  v1::DeformResponse first;
  auto again = OpenSession(*stub_, context, mesh_, e, v1::LAPLACIAN, &first);
  EXPECT_GT(first.positions_size(), 0) << "a closed session must give its slot back";
  again->WritesDone();
  EXPECT_TRUE(again->Finish().ok());
  for (size_t i = 1; i < open.size(); ++i) {
    open[i]->WritesDone();
    EXPECT_TRUE(open[i]->Finish().ok());
  }
}

TEST_F(Deform, SessionsInAllAreLimited) {
  server_->Stop(SIGTERM);
  ServerProcess two(data_.path(), {"--no-demo", "--max-sessions", "2"});
  client::Client client(OptionsFor(two));
  auto stub = v1::DeformService::NewStub(client.channel());
  const Edit e = BumpEdit(grid_);
  grpc::ClientContext c1, c2, c3;
  v1::DeformResponse first;
  auto s1 = OpenSession(*stub, c1, mesh_, e, v1::LAPLACIAN, &first);
  ASSERT_GT(first.positions_size(), 0);
  auto s2 = OpenSession(*stub, c2, mesh_, e, v1::ARAP, &first);
  ASSERT_GT(first.positions_size(), 0);
  auto s3 = OpenSession(*stub, c3, mesh_, e, v1::LAPLACIAN, &first);
  EXPECT_EQ(first.positions_size(), 0);
  const grpc::Status st = s3->Finish();
  EXPECT_EQ(st.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(st.error_message().find("--max-sessions (2)"), std::string::npos) << st.error_message();
  for (auto* s : {s1.get(), s2.get()}) {
    s->WritesDone();
    EXPECT_TRUE(s->Finish().ok());
  }
}

TEST_F(Deform, CliPrintsTheGrpcPositionsAsJson) {
  const Edit e = BumpEdit(grid_);
  const v1::DeformResponse grpc_answer = Call(RequestFor(mesh_, e, v1::COTANGENT));
  std::string fixed;
  for (uint32_t v : e.fixed) fixed += (fixed.empty() ? "" : ",") + std::to_string(v);
  char handle[160];
  std::snprintf(handle, sizeof handle, "%u=%.17g,%.17g,%.17g", e.handles[0], e.targets[0], e.targets[1], e.targets[2]);
  const auto r = RunCli(server_->target(),
                        {"deform", mesh_, "--weights", "cotan", "--fixed", fixed, "--handle", handle, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j["mesh"], mesh_);
  ASSERT_EQ(j["positions"].size(), static_cast<size_t>(grpc_answer.positions_size()));
  for (int i = 0; i < grpc_answer.positions_size(); ++i)
    EXPECT_EQ(j["positions"][static_cast<size_t>(i)].get<float>(), grpc_answer.positions(i)) << i;

  const auto bad = RunCli(server_->target(), {"deform", mesh_, "--handle", "3=1,2"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("--handle 3=1,2"), std::string::npos) << bad.err;
  const auto fixed_handle = RunCli(server_->target(), {"deform", mesh_, "--fixed", "3", "--handle", "3=1,2,3"});
  EXPECT_NE(fixed_handle.exit_code, 0);
  EXPECT_NE(fixed_handle.err.find("INVALID_ARGUMENT"), std::string::npos) << fixed_handle.err;
}

TEST_F(Deform, MeshOverMaxMeshVerticesIsResourceExhausted) {
  // Imported under the default limit, then served by a server with a lower one.
  server_->Stop(SIGTERM);
  ServerProcess small(data_.path(), {"--no-demo", "--max-mesh-vertices", "100"});
  client::Client client(OptionsFor(small));
  const v1::DeformRequest r = RequestFor(mesh_, BumpEdit(grid_), v1::UNIFORM);
  const grpc::Status status = StatusOf([&] { client.Deform(r); });
  const std::string& message = status.error_message();
  EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED);
  EXPECT_NE(message.find("max_mesh_vertices"), std::string::npos) << message;
  EXPECT_NE(message.find("289 vertices"), std::string::npos) << message;
}

}  // namespace
}  // namespace armature::testing
