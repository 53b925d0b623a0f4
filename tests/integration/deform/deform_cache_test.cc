// The unary Deform factorization cache (--deform-cache-mb) end to end: a
// repeated setup hits and gives exactly what a server without the cache
// gives (Laplacian and ARAP), other handle sets and setups miss, a mesh
// deleted or replaced under the same name is never answered from its old
// factorization, and the byte budget holds.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "armature/v1/deform.grpc.pb.h"
#include "support/client_helpers.h"
#include "support/deform_grid.h"
#include "support/metrics_scrape.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

constexpr char kHits[] = "armature_deform_cache_hits_total";
constexpr char kMisses[] = "armature_deform_cache_misses_total";
constexpr char kBytes[] = "armature_deform_cache_bytes";
constexpr char kEntries[] = "armature_deform_cache_entries";

// Same floats, bit for bit (EXPECT_EQ on floats would also pass for 0 == -0).
bool SameBits(const v1::DeformResponse& a, const v1::DeformResponse& b) {
  return a.positions_size() == b.positions_size() &&
         std::memcmp(a.positions().data(), b.positions().data(), sizeof(float) * a.positions_size()) == 0;
}

// The edit's handle moved to a second target.
Edit Moved(const Edit& e, double dx, double dz) {
  Edit m = e;
  m.targets[0] += dx;
  m.targets[2] += dz;
  return m;
}

// One server (and client) over a data dir.
struct Served {
  ServerProcess server;
  client::Client client;
  std::unique_ptr<v1::DeformService::Stub> stub;

  Served(const TempDir& data, std::vector<std::string> args)
      : server(data.path(), std::move(args)),
        client(OptionsFor(server)),
        stub(v1::DeformService::NewStub(client.channel())) {}
  v1::DeformResponse Call(const v1::DeformRequest& r) {
    return client.Call(&v1::DeformService::Stub::Deform, *stub, r);
  }
  double Metric(const std::string& name) { return Scrape(server).at(name); }
};

class DeformCache : public ::testing::Test {
 protected:
  void SetUp() override {
    grid_ = MakeGrid(17);
    edit_ = BumpEdit(grid_);
    Start({});
    const auto imported = served_->client.Import({"bump.obj", grid_.obj}, "bump");
    ASSERT_EQ(imported.asset().meshes_size(), 1);
    ASSERT_EQ(imported.asset().meshes(0).name(), "bump");
  }

  // (Re)starts the server on the same data dir with extra flags.
  void Start(std::vector<std::string> flags) {
    served_.reset();
    flags.insert(flags.begin(), "--no-demo");
    served_.emplace(data_, std::move(flags));
  }

  // A second server on the same data dir that keeps nothing: the fresh answer.
  v1::DeformResponse Fresh(const v1::DeformRequest& r) {
    Served uncached(data_, {"--no-demo", "--deform-cache-mb", "0"});
    const v1::DeformResponse answer = uncached.Call(r);
    EXPECT_EQ(uncached.Metric(kHits), 0);
    return answer;
  }

  TempDir data_;
  Grid grid_;
  Edit edit_;
  std::optional<Served> served_;
};

TEST_F(DeformCache, RepeatedLaplacianSetupHitsAndIsBitIdenticalToAFreshSolve) {
  Served& s = *served_;
  EXPECT_EQ(s.Metric(kHits), 0);
  EXPECT_EQ(s.Metric(kMisses), 0);
  EXPECT_EQ(s.Metric(kBytes), 0);
  const v1::DeformRequest a = RequestFor("bump", edit_, v1::COTANGENT);
  const v1::DeformResponse first = s.Call(a);
  EXPECT_EQ(s.Metric(kMisses), 1);
  EXPECT_EQ(s.Metric(kHits), 0);
  EXPECT_GT(s.Metric(kBytes), 0);
  const v1::DeformResponse again = s.Call(a);
  EXPECT_EQ(s.Metric(kHits), 1);
  EXPECT_EQ(s.Metric(kMisses), 1);
  EXPECT_TRUE(SameBits(first, again));

  // A drag: the same setup and handle, a new target, answered from the cache.
  const v1::DeformRequest b = RequestFor("bump", Moved(edit_, -0.2, 0.1), v1::COTANGENT);
  const v1::DeformResponse dragged = s.Call(b);
  EXPECT_EQ(s.Metric(kHits), 2);
  EXPECT_EQ(s.Metric(kMisses), 1);
  EXPECT_EQ(s.Metric(kEntries), 1);
  EXPECT_FALSE(SameBits(first, dragged))
      << "the second target must change the answer for the comparison to mean anything";
  const uint32_t h = edit_.handles[0];
  EXPECT_EQ(dragged.positions(static_cast<int>(3 * h)), static_cast<float>(edit_.targets[0] - 0.2));
  EXPECT_TRUE(SameBits(dragged, Fresh(b)));
}

TEST_F(DeformCache, CachedArapStartsFromRestAndEqualsAFreshSolve) {
  Served& s = *served_;
  v1::DeformRequest a = RequestFor("bump", edit_, v1::COTANGENT);
  a.set_method(v1::ARAP);
  v1::DeformRequest b = RequestFor("bump", Moved(edit_, -0.2, 0.1), v1::COTANGENT);
  b.set_method(v1::ARAP);
  const v1::DeformResponse first = s.Call(a);
  ASSERT_GT(first.iterations(), 1) << "ARAP must iterate for the warm-start question to arise";
  // Were the cached solver warm-started from `first`, this would differ from a fresh solve.
  const v1::DeformResponse dragged = s.Call(b);
  EXPECT_EQ(s.Metric(kHits), 1);
  EXPECT_EQ(s.Metric(kMisses), 1);
  const v1::DeformResponse fresh = Fresh(b);
  EXPECT_EQ(dragged.iterations(), fresh.iterations());
  EXPECT_TRUE(SameBits(dragged, fresh));
  // And back to the first target: the first answer again, not a continuation of the drag.
  EXPECT_TRUE(SameBits(s.Call(a), first));
  EXPECT_EQ(s.Metric(kHits), 2);
}

TEST_F(DeformCache, OtherHandlesOrSetupMiss) {
  Served& s = *served_;
  s.Call(RequestFor("bump", edit_, v1::UNIFORM));
  Edit other = edit_;
  other.handles = {grid_.at(3, grid_.n - 1)};
  s.Call(RequestFor("bump", other, v1::UNIFORM));
  EXPECT_EQ(s.Metric(kMisses), 2);
  Edit two = edit_;
  two.handles.push_back(other.handles[0]);
  two.targets.insert(two.targets.end(), {0.2, 1.0, 0.1});
  s.Call(RequestFor("bump", two, v1::UNIFORM));
  EXPECT_EQ(s.Metric(kMisses), 3);
  s.Call(RequestFor("bump", edit_, v1::COTANGENT));  // other weights
  EXPECT_EQ(s.Metric(kMisses), 4);
  Edit fewer_fixed = edit_;
  fewer_fixed.fixed.pop_back();
  s.Call(RequestFor("bump", fewer_fixed, v1::UNIFORM));
  EXPECT_EQ(s.Metric(kMisses), 5);
  EXPECT_EQ(s.Metric(kHits), 0);
  EXPECT_EQ(s.Metric(kEntries), 5);
  s.Call(RequestFor("bump", other, v1::UNIFORM));  // still there
  EXPECT_EQ(s.Metric(kHits), 1);
}

TEST_F(DeformCache, AMeshReimportedUnderTheSameNameIsNeverAnsweredFromItsOldFactorization) {
  Served& s = *served_;
  const v1::DeformRequest r = RequestFor("bump", edit_, v1::UNIFORM);
  const v1::DeformResponse old_answer = s.Call(r);
  // Same vertex count and triangles, other geometry: a request valid for both.
  const Grid taller = MakeGrid(grid_.n, 0.6f);
  const Grid flat = MakeGrid(grid_.n, 0.0f);
  s.client.DeleteAsset("bump");
  s.client.Import({"bump.obj", taller.obj}, "bump");
  const v1::DeformResponse after_delete = s.Call(r);
  EXPECT_TRUE(SameBits(after_delete, Fresh(r)));
  s.client.Import({"bump.obj", flat.obj}, "bump", "", /*replace=*/true);
  const v1::DeformResponse after_replace = s.Call(r);
  EXPECT_TRUE(SameBits(after_replace, Fresh(r)));
  EXPECT_EQ(s.Metric(kHits), 0);
  EXPECT_EQ(s.Metric(kMisses), 3);
  EXPECT_EQ(s.Metric(kEntries), 1) << "entries of meshes no longer in the catalog are dropped";
  for (const auto& [answer, geometry] : {std::pair{&after_delete, &taller}, std::pair{&after_replace, &flat}}) {
    // The bump's height shows in the answer: a stale factorization (and rest shape) would not.
    double largest = 0;
    for (int i = 0; i < answer->positions_size(); ++i)
      largest = std::max(largest, std::abs(double{answer->positions(i)} - double{old_answer.positions(i)}));
    EXPECT_GT(largest, 0.1);
    // Fixed vertices sit at the rest positions of the mesh served now.
    for (uint32_t f : edit_.fixed)
      for (int a = 0; a < 3; ++a)
        EXPECT_EQ(answer->positions(static_cast<int>(3 * f) + a), geometry->positions[3 * f + a]);
  }
}

TEST_F(DeformCache, SizeZeroKeepsNothing) {
  Start({"--deform-cache-mb", "0"});
  Served& s = *served_;
  const v1::DeformRequest r = RequestFor("bump", edit_, v1::COTANGENT);
  const v1::DeformResponse first = s.Call(r);
  EXPECT_TRUE(SameBits(s.Call(r), first));
  EXPECT_EQ(s.Metric(kHits), 0);
  EXPECT_EQ(s.Metric(kMisses), 2);
  EXPECT_EQ(s.Metric(kBytes), 0);
  EXPECT_EQ(s.Metric(kEntries), 0);
}

TEST_F(DeformCache, ATinyCacheEvictsTheLeastRecentlyUsedAndStaysUnderItsBudget) {
  // One entry's size, from a server with room.
  served_->Call(RequestFor("bump", edit_, v1::UNIFORM));
  const double entry = served_->Metric(kBytes);
  ASSERT_GT(entry, 0);
  const auto with_handle = [&](int i) {
    Edit e = edit_;
    e.handles = {grid_.at(i, grid_.n - 1)};
    return RequestFor("bump", e, v1::UNIFORM);
  };

  // Room for one entry (the three handles' entries have the same size), not two.
  const double budget_mb = 1.5 * entry / (1 << 20);
  Start({"--deform-cache-mb", std::to_string(budget_mb)});
  Served& s = *served_;
  for (int i : {4, 8, 12}) {
    s.Call(with_handle(i));
    EXPECT_LE(s.Metric(kBytes), budget_mb * (1 << 20)) << i;
    EXPECT_EQ(s.Metric(kEntries), 1) << i;
  }
  s.Call(with_handle(12));  // the last one stayed
  EXPECT_EQ(s.Metric(kHits), 1);
  s.Call(with_handle(4));  // the first one was evicted
  EXPECT_EQ(s.Metric(kHits), 1);
  EXPECT_EQ(s.Metric(kMisses), 4);

  // Smaller than one entry: nothing is kept, every call still answered.
  Start({"--deform-cache-mb", std::to_string(0.5 * entry / (1 << 20))});
  const v1::DeformResponse first = served_->Call(with_handle(4));
  EXPECT_TRUE(SameBits(served_->Call(with_handle(4)), first));
  EXPECT_EQ(served_->Metric(kHits), 0);
  EXPECT_EQ(served_->Metric(kBytes), 0);
}

}  // namespace
}  // namespace armature::testing
