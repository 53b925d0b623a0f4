// grpc.health.v1 answers SERVING for the whole server ("") and for each armature.v1 service by
// full name, and NOT_FOUND for a service that does not exist.
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include "grpc/health/v1/health.grpc.pb.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

using grpc::health::v1::Health;
using grpc::health::v1::HealthCheckRequest;
using grpc::health::v1::HealthCheckResponse;

TEST(Health, ReportsEachArmatureServiceByFullName) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  auto stub = Health::NewStub(grpc::CreateChannel(server.target(), grpc::InsecureChannelCredentials()));
  for (const std::string service :
       {"", "armature.v1.AssetService", "armature.v1.PoseService", "armature.v1.IkService", "armature.v1.MeshService",
        "armature.v1.DeformService", "armature.v1.AuthoringService", "armature.v1.CrowdService"}) {
    grpc::ClientContext context;
    context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(30));
    HealthCheckRequest request;
    request.set_service(service);
    HealthCheckResponse response;
    const grpc::Status status = stub->Check(&context, request, &response);
    ASSERT_TRUE(status.ok()) << "'" << service << "': " << status.error_message();
    EXPECT_EQ(response.status(), HealthCheckResponse::SERVING) << "'" << service << "'";
  }
  grpc::ClientContext context;
  HealthCheckRequest request;
  request.set_service("armature.v1.NoSuchService");
  HealthCheckResponse response;
  EXPECT_EQ(stub->Check(&context, request, &response).error_code(), grpc::StatusCode::NOT_FOUND);
}

}  // namespace
}  // namespace armature::testing
