// interpolation_test.gltf (Khronos): every sampler type against the glTF
// spec's formulas, computed here straight from the accessor bytes (the test
// reads the JSON and .bin itself, not through the importer):
//   STEP:        v_k on [t_k, t_k+1)
//   LINEAR:      (1−s)·v_k + s·v_k+1; rotations by slerp on the shorter arc
//   CUBICSPLINE: (2s³−3s²+1)·v_k + Δt(s³−2s²+s)·b_k + (−2s³+3s²)·v_k+1 + Δt(s³−s²)·a_k+1,
//                with (a, v, b) = (in-tangent, value, out-tangent) per key,
//                rotations normalized afterwards
// and the value held before the first and after the last key.
#include <cstring>
#include <set>

#include <gtest/gtest.h>

#include "armature/engine/anim/clip.h"
#include "../testing/mesh_test_util.h"

namespace armature {
namespace {

using Json = nlohmann::json;
using test_util::ReadFileBytes;
using test_util::SharedData;

// Accessor `index` as float rows of `width`, read from the raw buffer.
std::vector<std::vector<double>> Rows(const Json& gltf, const std::string& bin, int index) {
  const Json& a = gltf["accessors"][index];
  const Json& view = gltf["bufferViews"][a["bufferView"].get<int>()];
  EXPECT_EQ(a["componentType"].get<int>(), 5126);
  const std::string type = a["type"];
  const size_t width = type == "SCALAR" ? 1 : type == "VEC3" ? 3 : 4;
  const size_t stride = view.value("byteStride", 4 * width);
  const size_t offset = view.value("byteOffset", 0) + a.value("byteOffset", 0);
  std::vector<std::vector<double>> rows;
  for (size_t i = 0; i < a["count"].get<size_t>(); ++i) {
    std::vector<double> row;
    for (size_t c = 0; c < width; ++c) {
      float f;
      std::memcpy(&f, bin.data() + offset + i * stride + 4 * c, 4);
      row.push_back(f);
    }
    rows.push_back(row);
  }
  return rows;
}

std::vector<double> Combine(double a, const std::vector<double>& x, double b, const std::vector<double>& y) {
  std::vector<double> r(x.size());
  for (size_t i = 0; i < x.size(); ++i) r[i] = a * x[i] + b * y[i];
  return r;
}

std::vector<double> Normalized(std::vector<double> q) {
  double n = 0;
  for (double x : q) n += x * x;
  for (double& x : q) x /= std::sqrt(n);
  return q;
}

// The spec's sampler at time t: keys (times), per-key output rows.
std::vector<double> SpecSample(const std::string& interpolation, bool rotation, const std::vector<double>& times,
                               const std::vector<std::vector<double>>& out, double t) {
  const bool cubic = interpolation == "CUBICSPLINE";
  auto value = [&](size_t k) { return cubic ? out[3 * k + 1] : out[k]; };
  const size_t n = times.size();
  std::vector<double> result;
  if (t <= times.front())
    result = value(0);
  else if (t >= times.back())
    result = value(n - 1);
  else {
    size_t k = 0;
    while (!(t < times[k + 1])) ++k;
    const double dt = times[k + 1] - times[k], s = (t - times[k]) / dt;
    if (interpolation == "STEP") {
      result = value(k);
    } else if (interpolation == "LINEAR") {
      if (!rotation) {
        result = Combine(1 - s, value(k), s, value(k + 1));
      } else {
        const auto a = Normalized(value(k)), b = Normalized(value(k + 1));
        double d = 0;
        for (int i = 0; i < 4; ++i) d += a[i] * b[i];
        const double sign = d < 0 ? -1 : 1, theta = std::acos(std::min(1.0, std::abs(d)));
        result = theta < 1e-9 ? Combine(1 - s, a, s * sign, b)
                              : Combine(std::sin((1 - s) * theta) / std::sin(theta), a,
                                        sign * std::sin(s * theta) / std::sin(theta), b);
      }
    } else {
      const double s2 = s * s, s3 = s2 * s;
      result = Combine(2 * s3 - 3 * s2 + 1, value(k), dt * (s3 - 2 * s2 + s), out[3 * k + 2]);
      result = Combine(1, result, -2 * s3 + 3 * s2, value(k + 1));
      result = Combine(1, result, dt * (s3 - s2), out[3 * (k + 1)]);
    }
  }
  return rotation ? Normalized(result) : result;
}

TEST(GltfInterpolation, EverySamplerMatchesTheSpecFormulas) {
  const auto path = SharedData("gltf/interpolation_test.gltf");
  const auto text = ReadFileBytes(path);
  const auto bin = ReadFileBytes(SharedData("gltf/interpolation_test.bin"));
  if (!text || !bin) GTEST_SKIP() << "shared test data not found at " << path;
  const Json gltf = Json::parse(*text);
  auto contents = test_util::LoadGltfFile(path, "interp");
  ASSERT_TRUE(contents.ok()) << contents.status().message();
  ASSERT_EQ(contents->clips.size(), gltf["animations"].size());
  const Skeleton& skeleton = *contents->skeletons[0].skeleton;

  std::set<std::string> covered;
  for (size_t a = 0; a < gltf["animations"].size(); ++a) {
    const Json& anim = gltf["animations"][a];
    const auto& named = contents->clips[a];
    EXPECT_EQ(named.name, "interp." + anim["name"].get<std::string>());
    const Clip& clip = *named.clip;
    for (const Json& channel : anim["channels"]) {
      const Json& sampler = anim["samplers"][channel["sampler"].get<int>()];
      const std::string path_name = channel["target"]["path"];
      const std::string interpolation = sampler.value("interpolation", "LINEAR");
      covered.insert(interpolation + " " + path_name);
      const bool rotation = path_name == "rotation";
      std::vector<double> times;
      for (const auto& row : Rows(gltf, *bin, sampler["input"])) times.push_back(row[0]);
      const auto out = Rows(gltf, *bin, sampler["output"]);
      const int joint = skeleton.Find(gltf["nodes"][channel["target"]["node"].get<int>()]["name"].get<std::string>());
      ASSERT_GE(joint, 0);

      // Before, at and between keys, and after the end.
      std::vector<double> probe = {times.front() - 0.5, times.back() + 0.5};
      for (size_t k = 0; k < times.size(); ++k) {
        probe.push_back(times[k]);
        if (k + 1 < times.size())
          for (double f : {0.1, 0.37, 0.5, 0.83}) probe.push_back(times[k] + f * (times[k + 1] - times[k]));
      }
      std::vector<Trs> pose(skeleton.size());
      for (double t : probe) {
        ASSERT_TRUE(SampleClip(clip, t, {}, pose).ok());
        const Trs& trs = pose[static_cast<size_t>(joint)];
        const auto expected = SpecSample(interpolation, rotation, times, out, t);
        std::vector<double> actual;
        if (rotation) {
          actual = {trs.rotation.x(), trs.rotation.y(), trs.rotation.z(), trs.rotation.w()};
          // q and −q are the same rotation.
          double d = 0;
          for (int i = 0; i < 4; ++i) d += actual[i] * expected[i];
          if (d < 0)
            for (double& x : actual) x = -x;
        } else {
          const Eigen::Vector3d& v = path_name == "scale" ? trs.scale : trs.translation;
          actual = {v.x(), v.y(), v.z()};
        }
        for (size_t i = 0; i < expected.size(); ++i)
          EXPECT_NEAR(actual[i], expected[i], 1e-6) << anim["name"] << " " << path_name << " at t=" << t;
      }
    }
  }
  // The file exercises all three samplers on all three TRS paths.
  for (const char* want : {"STEP scale", "CUBICSPLINE scale", "STEP rotation", "CUBICSPLINE rotation",
                           "LINEAR rotation", "STEP translation", "CUBICSPLINE translation", "LINEAR translation"})
    EXPECT_TRUE(covered.count(want)) << want;
}

}  // namespace
}  // namespace armature
