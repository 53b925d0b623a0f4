// CreateClip on a real server: keys back exactly at key times, slerp between
// LINEAR keys, C¹ CUBIC tracks, Euler keys, a restart, replace/merge/delete.
#include <cmath>
#include <csignal>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "authoring/create_clip_support.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

// The textbook slerp along the shortest arc, written here so the server's is
// checked against an independent one.
Eigen::Quaterniond ReferenceSlerp(const Eigen::Quaterniond& a, Eigen::Quaterniond b, double u) {
  double c = a.coeffs().dot(b.coeffs());
  if (c < 0) {
    b.coeffs() = -b.coeffs();
    c = -c;
  }
  const double theta = std::acos(std::min(1.0, c));
  if (theta < 1e-9) return a;
  const double wa = std::sin((1 - u) * theta) / std::sin(theta), wb = std::sin(u * theta) / std::sin(theta);
  return Eigen::Quaterniond(Eigen::Vector4d(wa * a.coeffs() + wb * b.coeffs()));
}

class CreateClipTest : public ::testing::Test {
 protected:
  CreateClipTest() : server_(std::make_unique<ServerProcess>(data_.path())), client_(OptionsFor(*server_)) {}

  v1::CreateClipResponse Create(v1::CreateClipRequest request) { return client_.CreateClip(request); }

  TempDir data_;
  std::unique_ptr<ServerProcess> server_;
  client::Client client_;
  KeyMaker make_;
};

struct JointKeysValues {
  std::string joint;
  std::vector<double> times;
  std::vector<Eigen::Quaterniond> rotations;
  std::vector<Eigen::Vector3d> translations;
};

JointKeysValues MakeKeys(KeyMaker& make, const std::string& joint, int n) {
  JointKeysValues v{joint, make.Times(n), {}, {}};
  for (int k = 0; k < n; ++k) {
    v.rotations.push_back(make.Rotation());
    v.translations.push_back(make.Translation());
  }
  return v;
}

TEST_F(CreateClipTest, ReturnsItsKeysAtKeyTimesForEveryInterpolation) {
  const std::vector<std::pair<std::string, v1::Interpolation>> joints = {
      {"Head", v1::LINEAR}, {"Neck", v1::STEP}, {"LeftElbow", v1::CUBIC}, {"Hips", v1::INTERPOLATION_UNSPECIFIED}};
  v1::CreateClipRequest request;
  request.set_skeleton("demo_walk");
  request.set_name("keys");
  std::vector<JointKeysValues> keys;
  for (const auto& [joint, mode] : joints) {
    keys.push_back(MakeKeys(make_, joint, 7));
    *request.add_tracks() = Keys(joint, keys.back().times, keys.back().rotations, keys.back().translations, mode);
  }
  const auto response = Create(request);
  EXPECT_EQ(response.clip().name(), "keys");
  EXPECT_EQ(response.asset().name(), "keys");
  double last = 0;
  for (const auto& k : keys) last = std::max(last, k.times.back());
  EXPECT_NEAR(response.clip().duration(), last, 1e-6);
  EXPECT_EQ(response.clip().frames(), 7);

  double worst = 0;
  for (const JointKeysValues& k : keys) {
    const auto got = SampleLocal(client_, "keys", k.joint, k.times);
    ASSERT_EQ(got.size(), k.times.size());
    for (size_t i = 0; i < k.times.size(); ++i) {
      const Eigen::Vector4d q = Aligned(got[i].rotation, k.rotations[i]);
      for (int c = 0; c < 4; ++c) {
        EXPECT_TRUE(CloseRelative(q[c], k.rotations[i].coeffs()[c], 1e-6))
            << k.joint << " key " << i << " rotation " << q[c] << " vs " << k.rotations[i].coeffs()[c];
        worst = std::max(worst, std::abs(q[c] - k.rotations[i].coeffs()[c]));
      }
      for (int c = 0; c < 3; ++c) {
        EXPECT_TRUE(CloseRelative(got[i].translation[c], k.translations[i][c], 1e-6))
            << k.joint << " key " << i << " translation " << got[i].translation[c] << " vs " << k.translations[i][c];
        worst = std::max(worst, std::abs(got[i].translation[c] - k.translations[i][c]) /
                                    std::max(1.0, std::abs(k.translations[i][c])));
      }
    }
  }
  std::printf("[ measured ] worst relative error at key times: %.3g\n", worst);
}

// Times a float cannot hold (0.1 and 0.3 round up as floats, 0.7 down): a STEP
// key is still in effect from its own time, not a hair after it.
TEST_F(CreateClipTest, StepKeysHoldFromTheirOwnTimes) {
  const std::vector<double> times = {0.1, 0.3, 0.7};
  const std::vector<Eigen::Vector3d> values = {{1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  v1::CreateClipRequest request;
  request.set_skeleton("demo_walk");
  request.set_name("step");
  *request.add_tracks() = Keys("Head", times, {}, values, v1::STEP);
  Create(request);
  const auto got = SampleLocal(client_, "step", "Head", {0.1, 0.2999999, 0.3, 0.6999999, 0.7, 5});
  const std::vector<double> want = {1, 1, 2, 2, 3, 3};
  for (size_t i = 0; i < want.size(); ++i) EXPECT_EQ(got[i].translation.x(), want[i]) << i;
}

TEST_F(CreateClipTest, LinearKeysSlerpAndLerpBetweenKeys) {
  JointKeysValues k = MakeKeys(make_, "Head", 6);
  // One pair of keys in opposite hemispheres: the shortest arc is the one taken.
  k.rotations[3].coeffs() = -k.rotations[3].coeffs();
  v1::CreateClipRequest request;
  request.set_skeleton("demo_walk");
  request.set_name("linear");
  *request.add_tracks() = Keys("Head", k.times, k.rotations, k.translations, v1::LINEAR);
  Create(request);

  std::vector<double> times;
  std::vector<std::pair<size_t, double>> where;
  for (size_t s = 0; s + 1 < k.times.size(); ++s)
    for (double u : {0.1, 0.25, 0.5, 0.75, 0.9}) {
      times.push_back(k.times[s] + u * (k.times[s + 1] - k.times[s]));
      where.push_back({s, u});
    }
  const auto got = SampleLocal(client_, "linear", "Head", times);
  double worst = 0;
  for (size_t i = 0; i < times.size(); ++i) {
    const auto [s, u] = where[i];
    const Eigen::Quaterniond want = ReferenceSlerp(k.rotations[s], k.rotations[s + 1], u);
    const double angle = want.angularDistance(got[i].rotation);
    worst = std::max(worst, angle);
    EXPECT_LT(angle, 1e-5) << "segment " << s << " u " << u;
    const Eigen::Vector3d lerp = k.translations[s] + u * (k.translations[s + 1] - k.translations[s]);
    EXPECT_LT((got[i].translation - lerp).norm(), 1e-5) << "segment " << s << " u " << u;
  }
  std::printf("[ measured ] worst angle from an independent slerp: %.3g rad\n", worst);
}

// Slopes just left and right of time t by one-sided second-order differences.
struct Slopes {
  Eigen::VectorXd left, right;
};

Slopes SlopesAround(client::Client& client, const std::string& clip, const std::string& joint, double t,
                    const Eigen::Quaterniond& sign) {
  const double h = 2e-3;
  const auto s = SampleLocal(client, clip, joint, {t - 2 * h, t - h, t, t + h, t + 2 * h});
  auto vec = [&](size_t i) {
    Eigen::VectorXd v(7);
    v << s[i].translation, Aligned(s[i].rotation, sign);
    return v;
  };
  return {(3 * vec(2) - 4 * vec(1) + vec(0)) / (2 * h), (-3 * vec(2) + 4 * vec(3) - vec(4)) / (2 * h)};
}

TEST_F(CreateClipTest, CubicTracksAreC1ThroughTheirKeys) {
  // Sharp turns: linear slopes flip at every key, so a kink would show.
  const std::vector<double> times = {0, 0.4, 0.7, 1.3, 1.6};
  std::vector<Eigen::Quaterniond> rotations;
  std::vector<Eigen::Vector3d> translations;
  for (size_t k = 0; k < times.size(); ++k) {
    const double sign = k % 2 ? 1 : -1;
    rotations.push_back(
        Eigen::Quaterniond(Eigen::AngleAxisd(sign * 0.8, Eigen::Vector3d(1, k * 0.3, 0.2).normalized())));
    translations.push_back(Eigen::Vector3d(sign, 0.5 * k, -sign * 2));
  }
  for (auto [name, mode] : {std::pair{"cubic", v1::CUBIC}, std::pair{"kinked", v1::LINEAR}}) {
    v1::CreateClipRequest request;
    request.set_skeleton("demo_walk");
    request.set_name(name);
    *request.add_tracks() = Keys("Head", times, rotations, translations, mode);
    Create(request);
  }
  double worst_cubic = 0, least_linear = 1e9;
  for (size_t k = 1; k + 1 < times.size(); ++k) {
    const Slopes cubic = SlopesAround(client_, "cubic", "Head", times[k], rotations[k]);
    const double jump = (cubic.left - cubic.right).norm() / std::max(1.0, cubic.left.norm());
    worst_cubic = std::max(worst_cubic, jump);
    EXPECT_LT(jump, 5e-3) << "key " << k << ": left " << cubic.left.transpose() << " right " << cubic.right.transpose();
    const Slopes linear = SlopesAround(client_, "kinked", "Head", times[k], rotations[k]);
    least_linear = std::min(least_linear, (linear.left - linear.right).norm() / std::max(1.0, linear.left.norm()));
  }
  // The same keys LINEAR do kink there: the check above can fail.
  EXPECT_GT(least_linear, 0.5);
  std::printf("[ measured ] CUBIC slope jump at keys (relative): %.3g; LINEAR: at least %.3g\n", worst_cubic,
              least_linear);

  // The translation between keys is the engine's Catmull-Rom (hand-derived:
  // keys y = 0, 0.5, 1 at 0, 0.4, 0.7 → slope at 0.4 = parabola through the three).
  const double hp = 0.4, hn = 0.3, p0 = 0, p1 = 0.5, p2 = 1.0;
  const double m1 = ((p2 - p1) / hn * hp + (p1 - p0) / hp * hn) / (hp + hn), m0 = (p1 - p0) / hp;
  const double u = 0.5, h = 0.4;
  const double want = (2 * u * u * u - 3 * u * u + 1) * p0 + (u * u * u - 2 * u * u + u) * m0 * h +
                      (-2 * u * u * u + 3 * u * u) * p1 + (u * u * u - u * u) * m1 * h;
  EXPECT_NEAR(SampleLocal(client_, "cubic", "Head", {0.2})[0].translation.y(), want, 1e-6);
}

TEST_F(CreateClipTest, GivenTangentsAreTheCubicSplinesTangents) {
  // One segment, y from 0 to 1 over 2 s, out-tangent 3/s at the start, in-tangent 0 at the end.
  v1::CreateClipRequest request;
  request.set_skeleton("demo_walk");
  request.set_name("tangents");
  v1::JointKeys* k = request.add_tracks();
  k->set_joint("Head");
  k->set_interpolation(v1::CUBIC);
  for (double t : {0.0, 2.0}) k->add_times(t);
  for (double v : {0.0, 0.0, 0.0, 0.0, 1.0, 0.0}) k->add_translations(v);
  for (double v : {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}) k->mutable_translation_tangents()->add_in_tangents(v);
  for (double v : {0.0, 3.0, 0.0, 0.0, 0.0, 0.0}) k->mutable_translation_tangents()->add_out_tangents(v);
  Create(request);
  // Hermite at u = 0.5: h00·0 + h10·(3·2) + h01·1 + h11·0 = 0.125·6 + 0.5.
  EXPECT_NEAR(SampleLocal(client_, "tangents", "Head", {1.0})[0].translation.y(), 1.25, 1e-6);
}

TEST_F(CreateClipTest, EulerKeysComposeInTheNamedOrder) {
  v1::CreateClipRequest request;
  request.set_skeleton("demo_walk");
  request.set_name("euler");
  v1::JointKeys* k = request.add_tracks();
  k->set_joint("Chest");
  k->add_times(0);
  k->add_times(1);
  for (double d : {30.0, -45.0, 60.0, 0.0, 10.0, -20.0}) k->add_euler(d);
  k->set_euler_order("ZXY");
  Create(request);
  const double r = M_PI / 180;
  const Eigen::Quaterniond want = Eigen::AngleAxisd(30 * r, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(-45 * r, Eigen::Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(60 * r, Eigen::Vector3d::UnitY());
  EXPECT_LT(want.angularDistance(SampleLocal(client_, "euler", "Chest", {0})[0].rotation), 1e-6);
}

TEST_F(CreateClipTest, SurvivesARestartWithTheSameAnswers) {
  v1::CreateClipRequest request;
  request.set_skeleton("demo_walk");
  request.set_name("kept");
  JointKeysValues a = MakeKeys(make_, "Head", 5), b = MakeKeys(make_, "RightKnee", 4);
  *request.add_tracks() = Keys("Head", a.times, a.rotations, a.translations, v1::CUBIC);
  *request.add_tracks() = Keys("RightKnee", b.times, b.rotations, {}, v1::STEP);
  Create(request);
  std::vector<double> times;
  for (double t = 0; t < 2.5; t += 0.037) times.push_back(t);
  v1::EvaluateClipRequest r;
  r.set_clip("kept");
  for (double t : times) r.add_times(t);
  const auto before = client_.EvaluateClip(r);

  ASSERT_EQ(server_->Stop(SIGTERM), 0);
  server_ = std::make_unique<ServerProcess>(data_.path());
  client::Client again(OptionsFor(*server_));
  const auto after = again.EvaluateClip(r);
  ASSERT_EQ(after.poses_size(), before.poses_size());
  for (int i = 0; i < after.poses_size(); ++i)
    EXPECT_EQ(after.poses(i).SerializeAsString(), before.poses(i).SerializeAsString()) << "time " << times[i];
  EXPECT_EQ(again.GetClip("kept").frames(), 5);
}

TEST_F(CreateClipTest, ReplaceMergeAndDeleteTracks) {
  JointKeysValues head = MakeKeys(make_, "Head", 3), hips = MakeKeys(make_, "Hips", 3);
  v1::CreateClipRequest first;
  first.set_skeleton("demo_walk");
  first.set_name("edit");
  *first.add_tracks() = Keys("Head", head.times, head.rotations, {}, v1::LINEAR);
  *first.add_tracks() = Keys("Hips", hips.times, hips.rotations, hips.translations, v1::LINEAR);
  Create(first);
  // The same name again: ALREADY_EXISTS unless replace or merge.
  EXPECT_EQ(CodeOf([&] { Create(first); }), grpc::StatusCode::ALREADY_EXISTS);

  // Merge: Head's track replaced, Hips' deleted, Neck's added; nothing else changes.
  JointKeysValues head2 = MakeKeys(make_, "Head", 2), neck = MakeKeys(make_, "Neck", 2);
  v1::CreateClipRequest merge;
  merge.set_name("edit");
  merge.set_merge(true);
  *merge.add_tracks() = Keys("Head", head2.times, head2.rotations, {}, v1::LINEAR);
  merge.add_tracks()->set_joint("Hips");
  *merge.add_tracks() = Keys("Neck", neck.times, neck.rotations, {}, v1::LINEAR);
  const auto merged = Create(merge);
  EXPECT_EQ(merged.clip().frames(), 2);
  EXPECT_LT(head2.rotations[1].angularDistance(SampleLocal(client_, "edit", "Head", {head2.times[1]})[0].rotation),
            1e-6);
  EXPECT_LT(neck.rotations[0].angularDistance(SampleLocal(client_, "edit", "Neck", {neck.times[0]})[0].rotation), 1e-6);
  // Hips back at rest: the skeleton's rest values at every time.
  const v1::Skeleton skeleton = client_.GetSkeleton("demo_walk");
  const auto& rest = skeleton.joints(0);
  ASSERT_EQ(rest.name(), "Hips");
  for (const Local& l : SampleLocal(client_, "edit", "Hips", {0, hips.times[1], hips.times[2]})) {
    EXPECT_LT((l.translation - Eigen::Vector3d(rest.offset(0), rest.offset(1), rest.offset(2))).norm(), 1e-6);
    EXPECT_LT(l.rotation.angularDistance(Eigen::Quaterniond(rest.rest_rotation(0), rest.rest_rotation(1),
                                                            rest.rest_rotation(2), rest.rest_rotation(3))),
              1e-6);
  }
  // A second merge keeps the first merge's tracks it does not name.
  v1::CreateClipRequest only_neck;
  only_neck.set_name("edit");
  only_neck.set_merge(true);
  *only_neck.add_tracks() = Keys("Neck", neck.times, {neck.rotations[1], neck.rotations[0]}, {}, v1::STEP);
  Create(only_neck);
  EXPECT_LT(head2.rotations[0].angularDistance(SampleLocal(client_, "edit", "Head", {head2.times[0]})[0].rotation),
            1e-6);
  EXPECT_LT(neck.rotations[1].angularDistance(SampleLocal(client_, "edit", "Neck", {neck.times[0]})[0].rotation), 1e-6);

  // Replace: a new clip, the old tracks gone (Head back at rest).
  v1::CreateClipRequest replace;
  replace.set_skeleton("demo_walk");
  replace.set_name("edit");
  replace.set_replace(true);
  *replace.add_tracks() = Keys("Neck", neck.times, neck.rotations, {}, v1::LINEAR);
  Create(replace);
  const v1::Skeleton replaced = client_.GetSkeleton("demo_walk");
  const auto& head_rest = replaced.joints(12);
  ASSERT_EQ(head_rest.name(), "Head");
  EXPECT_LT(SampleLocal(client_, "edit", "Head", {head2.times[0]})[0].rotation.angularDistance(
                Eigen::Quaterniond(head_rest.rest_rotation(0), head_rest.rest_rotation(1), head_rest.rest_rotation(2),
                                   head_rest.rest_rotation(3))),
            1e-6);

  // Merge into nothing: NOT_FOUND naming the asset. Deleting the asset deletes the clip.
  merge.set_name("nothing");
  EXPECT_EQ(CodeOf([&] { Create(merge); }), grpc::StatusCode::NOT_FOUND);
  EXPECT_NE(MessageOf([&] { Create(merge); }).find("'nothing'"), std::string::npos);
  client_.DeleteAsset("edit");
  EXPECT_EQ(CodeOf([&] { client_.GetClip("edit"); }), grpc::StatusCode::NOT_FOUND);
}

}  // namespace
}  // namespace armature::testing
