// Validation of request fields, in one place. Each failure is
// INVALID_ARGUMENT (or NOT_FOUND / RESOURCE_EXHAUSTED) naming the field.
#pragma once

#include <array>
#include <span>
#include <string>
#include <vector>

#include <google/protobuf/repeated_field.h>

#include "armature/engine/anim/skeleton.h"
#include "armature/engine/math/rotation.h"
#include "armature/base/status.h"
#include "armature/v1/deform.pb.h"
#include "armature/v1/meshes.pb.h"
#include "armature/v1/motion.pb.h"
#include "server/rpc/limits.h"
#include "server/rpc/stream_pacing.h"

namespace armature::server {

// Every time finite and >= 0, at most `limits.max_times_per_request`, at least one.
Status ValidateTimes(std::span<const double> times, const Limits& limits, const std::string& field);

// A finite number, with the field named in the error.
Status ValidateFinite(double value, const std::string& field);

// Joint names → indices into the skeleton; empty names = every joint.
// NOT_FOUND names the unknown joint and the field.
StatusOr<std::vector<int>> ResolveJoints(const Skeleton& skeleton,
                                         const google::protobuf::RepeatedPtrField<std::string>& names,
                                         const std::string& field);

// Normalizes stream pacing in place (defaults: 30 fps, speed 1) and checks it.
Status ValidatePacing(StreamPacing& pacing, const Limits& limits);

// A clip time: finite and >= 0.
Status ValidateClipTime(double time, const std::string& field);

// A stream's source: exactly one of `clip` and `motion`, naming both fields.
Status ValidateClipOrMotion(const std::string& clip, bool has_motion);

// A motion's own numbers, before any clip is looked up: at least one layer
// (at most limits.max_motion_layers), each layer's clip named, weight in
// [0, 1], speed, timeOffset finite, referenceTime finite and >= 0, mask
// weights one per mask joint (or none) in [0, 1], enums known. Errors are
// INVALID_ARGUMENT naming `field` and the layer ("motion.layers[1] (clip 'Wave'): weight …").
Status ValidateMotion(const v1::Motion& motion, const Limits& limits, const std::string& field);

// An answer of about `bytes` (computed before any work: `how` says from
// what, e.g. "100000 times × 31 joints × 28 bytes") fits in one message:
// RESOURCE_EXHAUSTED naming --max-message-mb and the size otherwise.
Status ValidateReplySize(double bytes, const Limits& limits, const std::string& rpc, const std::string& how);

// An enum field's number is one the API defines (proto3 keeps unknown
// numbers, which would otherwise silently act as the default):
// INVALID_ARGUMENT naming the field and listing the allowed values.
Status ValidateEnum(int value, const google::protobuf::EnumDescriptor* type, const std::string& field);

// A required string field (a name) is given.
Status ValidateRequired(const std::string& value, const std::string& field);

// An Euler axis order: three of X, Y, Z (any case) such as "ZXY"; empty is
// "XYZ". INVALID_ARGUMENT naming `field` otherwise.
StatusOr<std::array<Axis, 3>> ParseEulerOrder(const std::string& order, const std::string& field);

}  // namespace armature::server
