#include "motion_file.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include <google/protobuf/util/json_util.h>

namespace armature::cli {

void ReadJsonMessageFile(const std::string& path, const std::string& flag, const std::string& what,
                         google::protobuf::Message& message) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(flag + " " + path + ": cannot read the file");
  std::ostringstream text;
  text << in.rdbuf();
  const auto status = google::protobuf::util::JsonStringToMessage(text.str(), &message);
  if (!status.ok())
    throw std::runtime_error(flag + " " + path + ": not " + what + ": " + std::string(status.message()));
}

v1::Motion ReadMotionFile(const std::string& path) {
  v1::Motion motion;
  ReadJsonMessageFile(path, "--motion", "a motion (proto3 JSON of armature.v1.Motion)", motion);
  return motion;
}

nlohmann::json RootMotionJson(const v1::Pose& root_motion) {
  return {{"translation", root_motion.translations()}, {"rotation", root_motion.rotations()}};
}

}  // namespace armature::cli
