// How poses print: the JSON shape `armature pose` documents, and a table.
#pragma once

#include <string>

#include <google/protobuf/repeated_field.h>
#include <nlohmann/json.hpp>

#include "armature/v1/types.pb.h"

namespace armature::cli {

// {"clip"/"skeleton":…, "time":…, "space":…, "joints":[{"name","parent","translation","rotation"}]} minus the
// header fields, which callers add: just the "joints" array here.
nlohmann::json PoseJointsJson(const v1::Skeleton& skeleton, const google::protobuf::RepeatedField<int32_t>& joints,
                              const v1::Pose& pose);
void PrintPoseTable(const v1::Skeleton& skeleton, const google::protobuf::RepeatedField<int32_t>& joints,
                    const v1::Pose& pose);

}  // namespace armature::cli
