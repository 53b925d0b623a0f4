// The deformation session's logic without gRPC, over a small sheet: the
// start answers the rest shape as index 0, each move its number, and a bad
// message names its field.
#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "server/deform/deform_session.h"

namespace armature::server {
namespace {

using test_util::ParsedAsset;

// A 3×3 sheet: bottom row (0, 1, 2) fixed, the top middle (7) the handle.
constexpr char kSheetObj[] =
    "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nv 0 2 0\nv 1 2 0\nv 2 2 0\n"
    "f 1 2 5\nf 1 5 4\nf 2 3 6\nf 2 6 5\nf 4 5 8\nf 4 8 7\nf 5 6 9\nf 5 9 8\n";

std::shared_ptr<const Catalog> SheetCatalog() {
  std::map<std::string, std::shared_ptr<const StoredAsset>> assets;
  assets["sheet"] = ParsedAsset("sheet", AssetFormat::kObj, kSheetObj);
  auto catalog = BuildCatalog(std::move(assets));
  EXPECT_TRUE(catalog.ok()) << catalog.status().message();
  return std::move(*catalog);
}

class DeformSessionLogic : public ::testing::Test {
 protected:
  v1::DeformSessionRequest Start(const std::string& mesh) const {
    v1::DeformSessionRequest r;
    r.mutable_start()->mutable_setup()->set_mesh(mesh);
    for (uint32_t v : {0u, 1u, 2u}) r.mutable_start()->mutable_setup()->add_fixed(v);
    r.mutable_start()->add_handle_indices(7);
    return r;
  }
  static v1::DeformSessionRequest Move(std::initializer_list<double> positions) {
    v1::DeformSessionRequest r;
    for (double v : positions) r.mutable_move()->add_positions(v);
    return r;
  }
  std::shared_ptr<const Catalog> catalog_ = SheetCatalog();
  std::string mesh_ = catalog_->meshes.empty() ? "" : catalog_->meshes.begin()->first;
  const Limits limits_;
  DeformSession session_{[this] { return catalog_; }, limits_};
  v1::DeformResponse response_;
};

TEST_F(DeformSessionLogic, StartAnswersTheRestShapeThenEachMoveInOrder) {
  ASSERT_FALSE(mesh_.empty());
  const Status started = session_.Start({}, Start(mesh_), &response_);
  ASSERT_TRUE(started.ok()) << started.message();
  EXPECT_EQ(response_.index(), 0u);
  ASSERT_EQ(response_.positions_size(), 27);
  EXPECT_NEAR(response_.positions(3 * 7 + 1), 2.0, 1e-6);  // the handle at rest
  for (uint64_t k = 1; k <= 2; ++k) {
    response_.Clear();
    const Status moved = session_.Answer(Move({1.0, 2.0 + 0.1 * static_cast<double>(k), 0.5}), &response_);
    ASSERT_TRUE(moved.ok()) << moved.message();
    EXPECT_EQ(response_.index(), k);
    EXPECT_FLOAT_EQ(response_.positions(3 * 7 + 2), 0.5f);  // the handle on its target
    EXPECT_FLOAT_EQ(response_.positions(0), 0.0f);          // a fixed vertex held
  }
}

TEST_F(DeformSessionLogic, MessagesOutOfPlaceAreRefusedNamingTheField) {
  const Status first = session_.Start({}, Move({1, 2, 3}), &response_);
  EXPECT_EQ(first.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(first.message().rfind("start: the first message", 0), 0u) << first.message();

  EXPECT_EQ(session_.Start({}, Start("nope"), &response_).code(), StatusCode::kNotFound);

  ASSERT_TRUE(session_.Start({}, Start(mesh_), &response_).ok());
  const Status restart = session_.Answer(Start(mesh_), &response_);
  EXPECT_EQ(restart.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(restart.message().rfind("move: messages after the first", 0), 0u) << restart.message();
  const Status short_move = session_.Answer(Move({1}), &response_);
  EXPECT_EQ(short_move.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(short_move.message().find("move[1].positions"), std::string::npos) << short_move.message();
}

}  // namespace
}  // namespace armature::server
