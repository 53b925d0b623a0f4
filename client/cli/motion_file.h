// Motion files for `--motion FILE.json`: the Motion message as proto3 JSON
// ({"layers":[{"clip":…,"weight":…}],"sync":…,"rootMotion":…}).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "armature/v1/motion.pb.h"
#include "armature/v1/types.pb.h"

namespace armature::cli {

// Reads and parses FILE.json; throws std::runtime_error naming the file and
// what is wrong (unreadable, not JSON, an unknown field or enum name).
v1::Motion ReadMotionFile(const std::string& path);

// An EXTRACT answer's root motion as {"translation":[x,y,z],"rotation":[w,x,y,z]}.
nlohmann::json RootMotionJson(const v1::Pose& root_motion);

}  // namespace armature::cli
