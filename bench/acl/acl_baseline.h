// ACL 2.1 (../shared/third_party, header-only, MIT) as the baseline of
// vs_acl_bench.cc: our parsed clip as ACL's raw track list (the clip sampled
// at the frames we compress at, each track's parent, the rest pose as its
// default value, our bound as its precision and shell distance), compressed
// with ACL's default settings and qvvf error metric, and sampled into its own
// output (rtm::qvvf per joint).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <acl/compression/compress.h>
#include <acl/compression/track_array.h>
#include <acl/compression/transform_error_metrics.h>
#include <acl/core/ansi_allocator.h>
#include <acl/decompression/decompress.h>

#include "armature/engine/anim/clip.h"
#include "armature/engine/anim/compression/compressed_clip.h"

namespace armature::acl_baseline {

inline acl::ansi_allocator& Allocator() {
  static acl::ansi_allocator allocator;
  return allocator;
}

inline rtm::qvvf ToQvv(const Trs& t) {
  const rtm::quatf q =
      rtm::quat_normalize(rtm::quat_set(static_cast<float>(t.rotation.x()), static_cast<float>(t.rotation.y()),
                                        static_cast<float>(t.rotation.z()), static_cast<float>(t.rotation.w())));
  return rtm::qvv_set(q,
                      rtm::vector_set(static_cast<float>(t.translation.x()), static_cast<float>(t.translation.y()),
                                      static_cast<float>(t.translation.z())),
                      rtm::vector_set(static_cast<float>(t.scale.x()), static_cast<float>(t.scale.y()),
                                      static_cast<float>(t.scale.z())));
}

inline Trs ToTrs(const rtm::qvvf& q) {
  Trs t;
  t.rotation = Eigen::Quaterniond(rtm::quat_get_w(q.rotation), rtm::quat_get_x(q.rotation), rtm::quat_get_y(q.rotation),
                                  rtm::quat_get_z(q.rotation));
  t.translation = Eigen::Vector3d(rtm::vector_get_x(q.translation), rtm::vector_get_y(q.translation),
                                  rtm::vector_get_z(q.translation));
  t.scale = Eigen::Vector3d(rtm::vector_get_x(q.scale), rtm::vector_get_y(q.scale), rtm::vector_get_z(q.scale));
  return t;
}

// The raw track list: `frames` of the clip as SampleClip gives them.
inline acl::track_array_qvvf RawTracks(const Clip& clip, const FrameGrid& frames, const ErrorBound& bound) {
  const Skeleton& skeleton = *clip.skeleton;
  const uint32_t joints = static_cast<uint32_t>(skeleton.size());
  const uint32_t samples = static_cast<uint32_t>(frames.count);
  const float rate = frames.frame_time > 0 ? static_cast<float>(1.0 / frames.frame_time) : 30.f;
  acl::track_array_qvvf raw(Allocator(), joints);
  std::vector<std::vector<Trs>> poses(samples, std::vector<Trs>(joints));
  for (uint32_t f = 0; f < samples; ++f) (void)SampleClip(clip, frames.Time(f), {}, poses[f]);
  for (uint32_t j = 0; j < joints; ++j) {
    acl::track_desc_transformf desc;
    desc.output_index = j;
    desc.parent_index =
        skeleton.parents[j] < 0 ? acl::k_invalid_track_index : static_cast<uint32_t>(skeleton.parents[j]);
    desc.precision = static_cast<float>(bound.precision);
    desc.shell_distance = static_cast<float>(bound.shell_distance);
    desc.default_value = ToQvv(skeleton.rest[j]);
    acl::track_qvvf track = acl::track_qvvf::make_reserve(desc, Allocator(), samples, rate);
    for (uint32_t f = 0; f < samples; ++f) track[f] = ToQvv(poses[f][j]);
    raw[j] = std::move(track);
  }
  return raw;
}

struct CompressedTracksDeleter {
  void operator()(acl::compressed_tracks* t) const {
    if (t) Allocator().deallocate(t, t->get_size());
  }
};
using CompressedTracks = std::unique_ptr<acl::compressed_tracks, CompressedTracksDeleter>;

// ACL's default settings and qvvf error metric; null with `error` on failure.
inline CompressedTracks Compress(const acl::track_array_qvvf& raw, std::string& error) {
  static acl::qvvf_transform_error_metric metric;
  acl::compression_settings settings = acl::get_default_compression_settings();
  settings.error_metric = &metric;
  acl::output_stats stats;
  acl::compressed_tracks* out = nullptr;
  const acl::error_result result = acl::compress_track_list(Allocator(), raw, settings, out, stats);
  if (result.any()) {
    error = result.c_str();
    return nullptr;
  }
  return CompressedTracks(out);
}

// Writes ACL's output into a qvvf per joint; default sub-tracks are the rest pose.
struct PoseWriter : acl::track_writer {
  rtm::qvvf* out = nullptr;
  const rtm::qvvf* rest = nullptr;

  static constexpr acl::default_sub_track_mode get_default_rotation_mode() {
    return acl::default_sub_track_mode::variable;
  }
  static constexpr acl::default_sub_track_mode get_default_translation_mode() {
    return acl::default_sub_track_mode::variable;
  }
  static constexpr acl::default_sub_track_mode get_default_scale_mode() {
    return acl::default_sub_track_mode::variable;
  }
  rtm::quatf RTM_SIMD_CALL get_variable_default_rotation(uint32_t i) const { return rest[i].rotation; }
  rtm::vector4f RTM_SIMD_CALL get_variable_default_translation(uint32_t i) const { return rest[i].translation; }
  rtm::vector4f RTM_SIMD_CALL get_variable_default_scale(uint32_t i) const { return rest[i].scale; }
  void RTM_SIMD_CALL write_rotation(uint32_t i, rtm::quatf_arg0 r) { out[i].rotation = r; }
  void RTM_SIMD_CALL write_translation(uint32_t i, rtm::vector4f_arg0 t) { out[i].translation = t; }
  void RTM_SIMD_CALL write_scale(uint32_t i, rtm::vector4f_arg0 s) { out[i].scale = s; }
};

using Context = acl::decompression_context<acl::default_transform_decompression_settings>;

}  // namespace armature::acl_baseline
