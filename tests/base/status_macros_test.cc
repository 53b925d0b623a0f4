// ARMATURE_ASSIGN_OR_RETURN and ARMATURE_RETURN_IF_ERROR: the value taken, or the
// Status returned unchanged from the enclosing function.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "armature/base/status.h"

namespace armature {
namespace {

StatusOr<std::unique_ptr<int>> MakeInt(int v) {
  if (v < 0) return Status::InvalidArgument("negative: " + std::to_string(v));
  return std::make_unique<int>(v);
}

StatusOr<int> Doubled(int v) {
  ARMATURE_ASSIGN_OR_RETURN(auto p, MakeInt(v));            // move-only value
  ARMATURE_ASSIGN_OR_RETURN(const auto q, MakeInt(v + 1));  // two on one scope
  return *p + *q - 1;
}

Status Check(int v) {
  ARMATURE_ASSIGN_OR_RETURN(auto p, MakeInt(v));
  ARMATURE_RETURN_IF_ERROR(*p > 10 ? Status(StatusCode::kOutOfRange, "over 10") : Status::Ok());
  return Status::Ok();
}

TEST(StatusMacros, AssignOrReturnTakesTheValue) {
  StatusOr<int> r = Doubled(4);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(*r, 8);
}

TEST(StatusMacros, AssignOrReturnReturnsTheStatus) {
  StatusOr<int> r = Doubled(-3);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(r.status().message(), "negative: -3");
  EXPECT_EQ(Check(-1).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(Check(11).code(), StatusCode::kOutOfRange);
  EXPECT_TRUE(Check(3).ok());
}

}  // namespace
}  // namespace armature
