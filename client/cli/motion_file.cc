#include "motion_file.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include <google/protobuf/util/json_util.h>

namespace armature::cli {

v1::Motion ReadMotionFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("--motion " + path + ": cannot read the file");
  std::ostringstream text;
  text << in.rdbuf();
  v1::Motion motion;
  const auto status = google::protobuf::util::JsonStringToMessage(text.str(), &motion);
  if (!status.ok())
    throw std::runtime_error("--motion " + path + ": not a motion (proto3 JSON of armature.v1.Motion): " +
                             std::string(status.message()));
  return motion;
}

nlohmann::json RootMotionJson(const v1::Pose& root_motion) {
  return {{"translation", root_motion.translations()}, {"rotation", root_motion.rotations()}};
}

}  // namespace armature::cli
