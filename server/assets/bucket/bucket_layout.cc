#include "server/assets/bucket/bucket_layout.h"

#include <openssl/sha.h>

#include <chrono>
#include <ctime>

#include <nlohmann/json.hpp>

#include "server/assets/asset_record_json.h"
#include "server/assets/file_io.h"

namespace armature::server {
using json = nlohmann::json;
namespace {

constexpr std::string_view kVersions = "versions/";
constexpr size_t kTimeChars = 23;  // "yyyymmddThhmmss.uuuuuuZ"

std::string VersionTime(std::chrono::system_clock::time_point t) {
  const auto us = std::chrono::duration_cast<std::chrono::microseconds>(t.time_since_epoch()).count();
  const std::time_t seconds = us / 1000000;
  std::tm tm{};
  gmtime_r(&seconds, &tm);
  char buf[40];
  const size_t n = std::strftime(buf, sizeof buf, "%Y%m%dT%H%M%S", &tm);
  std::snprintf(buf + n, sizeof buf - n, ".%06lldZ", static_cast<long long>(us % 1000000));
  return buf;
}

std::chrono::system_clock::time_point ParseVersionTime(std::string_view version) {
  std::tm tm{};
  const std::string text(version.substr(0, kTimeChars));
  if (text.size() < kTimeChars || !strptime(text.c_str(), "%Y%m%dT%H%M%S", &tm)) return {};
  const long long us = std::atoll(text.c_str() + 16);
  return std::chrono::system_clock::from_time_t(timegm(&tm)) + std::chrono::microseconds(us);
}

json ObjectToJson(const StoredObject& o) { return {{"key", o.key}, {"size", o.size}, {"sha256", o.sha256}}; }

StoredObject ObjectFromJson(const json& j) {
  return {j.at("key").get<std::string>(), j.at("size").get<int64_t>(), j.at("sha256").get<std::string>()};
}

}  // namespace

std::string NewVersion(std::string_view after) {
  // Whole microseconds, as written: a version of the same microsecond as `after` must still sort after it.
  auto t = std::chrono::time_point_cast<std::chrono::microseconds>(std::chrono::system_clock::now());
  // A replica whose clock lags still orders its write after the one it saw.
  if (const auto seen = ParseVersionTime(after); seen >= t)
    t = std::chrono::time_point_cast<std::chrono::microseconds>(seen) + std::chrono::microseconds(1);
  std::string id = RandomSuffix();
  id.insert(0, 16 - std::min<size_t>(16, id.size()), '0');
  return VersionTime(t) + "-" + id;
}

std::string VersionsPrefix(const std::string& prefix) { return prefix + std::string(kVersions); }

std::string VersionKey(const std::string& prefix, const std::string& name, const std::string& version) {
  return VersionsPrefix(prefix) + name + "/" + version;
}

std::string ObjectKey(const std::string& prefix, const std::string& name, const std::string& version,
                      const std::string& file) {
  return prefix + "objects/" + name + "/" + version + "/" + file;
}

std::map<std::string, std::vector<std::string>> VersionsByName(const std::vector<ObjectEntry>& listing,
                                                               const std::string& prefix) {
  std::map<std::string, std::vector<std::string>> versions;
  const std::string start = VersionsPrefix(prefix);
  for (const ObjectEntry& entry : listing) {
    if (!entry.key.starts_with(start)) continue;
    const std::string rest = entry.key.substr(start.size());
    const size_t slash = rest.find('/');
    if (slash == std::string::npos || slash == 0 || rest.size() - slash - 1 < kTimeChars) continue;
    versions[rest.substr(0, slash)].push_back(rest.substr(slash + 1));
  }
  for (auto& [name, list] : versions) std::sort(list.begin(), list.end());
  return versions;
}

std::string VersionRecordToJson(const VersionRecord& v) {
  if (v.deleted) return json{{"name", v.record.name}, {"version", v.record.version}, {"deleted", true}}.dump();
  json j = RecordToJson(v.record);
  j["source"] = ObjectToJson(v.source);
  json resources = json::object();
  for (const auto& [uri, object] : v.resources) resources[uri] = ObjectToJson(object);
  j["objects"] = resources;
  return j.dump();
}

StatusOr<VersionRecord> VersionRecordFromJson(std::string_view text) {
  const json j = json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return Status::InvalidArgument("version record: not JSON");
  VersionRecord v;
  try {
    if (j.value("deleted", false)) {
      v.deleted = true;
      v.record.name = j.at("name").get<std::string>();
      v.record.version = j.at("version").get<std::string>();
      return v;
    }
    ARMATURE_ASSIGN_OR_RETURN(v.record, RecordFromJson(j));
    v.source = ObjectFromJson(j.at("source"));
    for (const auto& [uri, object] : j.at("objects").items()) v.resources[uri] = ObjectFromJson(object);
  } catch (const json::exception& e) {
    return Status::InvalidArgument(std::string("version record: ") + e.what());
  }
  if (v.resources.size() != v.record.resources.size())
    return Status::InvalidArgument("version record: its objects and resources differ");
  ARMATURE_RETURN_IF_ERROR(CheckRecordPaths(v.record).WithContext("version record: "));
  return v;
}

std::string Sha256Hex(std::string_view bytes) {
  unsigned char digest[SHA256_DIGEST_LENGTH];
  SHA256(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), digest);
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (unsigned char b : digest) {
    out += kHex[b >> 4];
    out += kHex[b & 15];
  }
  return out;
}

}  // namespace armature::server
