#include "server/assets/file_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <random>
#include <sstream>
#include <vector>

namespace armature::server {
namespace fs = std::filesystem;

namespace {

// Writes all of `bytes` to `fd`; 0 or the errno of the failure.
int WriteAll(int fd, std::string_view bytes) {
  size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return n < 0 ? errno : ENOSPC;  // a write of 0 bytes to a regular file: no room
    written += static_cast<size_t>(n);
  }
  return 0;
}

}  // namespace

std::string RandomSuffix() {
  static thread_local std::mt19937_64 rng{std::random_device{}()};
  std::ostringstream s;
  s << std::hex << rng();
  return s.str();
}

StatusOr<std::string> ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Status::NotFound("cannot read " + path.string());
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

Status DataDirError(const fs::path& dir, int err, std::string_view action) {
  if (err == ENOSPC || err == EDQUOT)
    return Status::ResourceExhausted("data dir " + dir.string() + ": no space left on device");
  return Status::Internal("data dir " + dir.string() + ": cannot " + std::string(action) + ": " + std::strerror(err));
}

Status WriteFileAtomic(const fs::path& dir, const std::string& relative, std::string_view bytes) {
  const fs::path path = dir / relative;
  std::string tmp_name = ".";  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on "." + string
  tmp_name += path.filename().string();
  tmp_name += ".tmp-";
  tmp_name += RandomSuffix();
  const fs::path tmp = path.parent_path() / tmp_name;
  const std::string action = "write " + relative;
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return DataDirError(dir, errno, action);
  int err = WriteAll(fd, bytes);
  if (err == 0 && ::fsync(fd) != 0) err = errno;  // a full NFS or thin disk may say so only here
  if (::close(fd) != 0 && err == 0) err = errno;
  if (err == 0 && ::rename(tmp.c_str(), path.c_str()) != 0) err = errno;
  if (err != 0) {
    ::unlink(tmp.c_str());
    return DataDirError(dir, err, action);
  }
  const int dfd = ::open(path.parent_path().c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    (void)::fsync(dfd);
    ::close(dfd);
  }
  return Status::Ok();
}

bool AllocateFile(const fs::path& path, int64_t bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  int err = ::posix_fallocate(fd, 0, bytes);
  if (err == EOPNOTSUPP || err == EINVAL) {  // no fallocate here (some NFS): real zeros take the blocks
    const std::vector<char> zeros(static_cast<size_t>(bytes), 0);
    err = ::lseek(fd, 0, SEEK_SET) == 0 ? WriteAll(fd, {zeros.data(), zeros.size()}) : errno;
  }
  if (err == 0 && ::fsync(fd) != 0) err = errno;
  ::close(fd);
  return err == 0;
}

}  // namespace armature::server
