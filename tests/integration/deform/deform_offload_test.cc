// Long factorizations do not hold gRPC's callback threads: while several
// unary Deform calls on a large mesh are factoring, a health check is
// answered before the first of them finishes (they run on the deform
// service's own pool).
#include <atomic>
#include <future>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/deform_grid.h"
#include "support/metrics_scrape.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

TEST(DeformOffload, HealthIsAnsweredWhileFactorizationsRun) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo", "--deform-cache-mb", "0"});
  client::Client client(OptionsFor(server));
  const Grid grid = MakeGrid(250);  // 62,500 vertices: each factorization takes about a second
  client.Import({"big.obj", grid.obj}, "big");
  const Edit edit = BumpEdit(grid);

  constexpr int kCalls = 6;  // more than the callback threads a 2-core machine gets
  std::atomic<int> finished{0};
  std::vector<std::future<int>> deforms;
  for (int k = 0; k < kCalls; ++k)
    deforms.push_back(std::async(std::launch::async, [&, k] {
      // The test asserts order, not speed: six factorizations at once on a
      // loaded 2-core machine can take far longer than the usual 30 s.
      client::ClientOptions options = OptionsFor(server);
      options.timeout = std::chrono::seconds(240);
      client::Client c(options);
      v1::DeformRequest r = RequestFor("big", edit, v1::UNIFORM);
      r.mutable_handles(0)->set_position(2, 0.1 * (k + 1));
      const int n = c.Deform(r).positions_size();
      finished.fetch_add(1);
      return n;
    }));
  // Once every call has reached the server (a factorization of this mesh
  // takes far longer than the calls take to arrive), ask for health.
  const std::string in_flight = "armature_rpc_in_flight{method=\"armature.v1.DeformService/Deform\"}";
  EXPECT_TRUE(WaitFor([&] { return ScrapeSample(server, in_flight) == kCalls; }, 60))
      << in_flight << " = " << ScrapeSample(server, in_flight) << ", " << finished.load() << " finished";
  EXPECT_TRUE(client::Client(OptionsFor(server)).Healthy());
  const int done_at_health = finished.load();
  for (auto& d : deforms) EXPECT_EQ(d.get(), 3 * grid.n * grid.n);
  // Health did not queue behind the factorizations (with them on the
  // callback threads it waited for one to finish).
  EXPECT_EQ(done_at_health, 0) << "health was answered only after " << done_at_health << " factorizations had finished";
}

}  // namespace
}  // namespace armature::testing
