// An flock(2) on data_dir/.lock, held for a scope. It serializes the
// manifest's read-modify-writes between the servers that share a data dir
// (replicas on one ReadWriteMany volume): writers take it exclusive,
// readers of another writer's changes shared. Works across hosts where the
// file system supports flock (local disks, NFSv4, CephFS, EFS).
#pragma once

#include <filesystem>

#include "armature/base/status.h"

namespace armature::server {

class DataDirLock {
 public:
  enum class Mode { kShared, kExclusive };

  // Blocks until the lock is held. INTERNAL if the lock file cannot be opened.
  static StatusOr<DataDirLock> Acquire(const std::filesystem::path& data_dir, Mode mode);

  DataDirLock(DataDirLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }
  DataDirLock& operator=(DataDirLock&&) = delete;
  ~DataDirLock();

 private:
  explicit DataDirLock(int fd) : fd_(fd) {}
  int fd_ = -1;  // its own open file description, so threads of one process exclude each other too
};

}  // namespace armature::server
