// Motion files for `--motion FILE.json`: the Motion message as proto3 JSON
// ({"layers":[{"clip":…,"weight":…}],"sync":…,"rootMotion":…}).
#pragma once

#include <string>

#include <google/protobuf/message.h>
#include <nlohmann/json.hpp>

#include "armature/v1/motion.pb.h"
#include "armature/v1/types.pb.h"

namespace armature::cli {

// Reads FILE.json (given as `flag`) into `message` as proto3 JSON; throws
// std::runtime_error naming the flag, the file and what is wrong, with
// `what` saying what the file should be.
void ReadJsonMessageFile(const std::string& path, const std::string& flag, const std::string& what,
                         google::protobuf::Message& message);

// Reads and parses FILE.json; throws std::runtime_error naming the file and
// what is wrong (unreadable, not JSON, an unknown field or enum name).
v1::Motion ReadMotionFile(const std::string& path);

// An EXTRACT answer's root motion as {"translation":[x,y,z],"rotation":[w,x,y,z]}.
nlohmann::json RootMotionJson(const v1::Pose& root_motion);

}  // namespace armature::cli
