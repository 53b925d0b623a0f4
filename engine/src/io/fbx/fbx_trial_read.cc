// assimp's FBX reader first reads the bytes in a child process, and the
// importer reads them itself only once that read succeeded.
//
// Why: libassimp 5.2 leaks what it has built when its FBX reader throws.
// Its parser's scopes and the document's objects are raw pointers, freed
// by destructors that a throwing constructor never runs. A truncated
// 12 KB file leaked 45 KB. A 64 MB upload cut short could leak hundreds
// of MB, and the memory is never given back. In the child, that memory
// goes when the child exits. A crash or a hang in assimp ends only the
// child too: the import is refused with the reason, and a read that takes
// over kTrialReadSeconds is killed.
//
// The cost is a second read of every good file. A failed read answers
// with assimp's message, as the in-process read did.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <string>

#include "fbx_importer.h"

namespace armature::fbx_internal {

namespace {

// What the child reports: one byte of StatusCode, then the message.
constexpr size_t kMaxReport = 4096;

void WriteAll(int fd, const char* data, size_t size) {
  while (size > 0) {
    const ssize_t n = ::write(fd, data, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    data += n;
    size -= static_cast<size_t>(n);
  }
}

// The child: reads, reports, and leaves without running the parent's
// exit handlers or destructors (its threads are not here). It holds none
// of the parent's sockets and files, and dies with the parent's thread,
// so a server that stops is not kept on its port by a reader.
[[noreturn]] void ReadAndReport(std::string_view bytes, int report_fd, pid_t parent) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(1);  // the parent died before the line above
  if (report_fd > 3) ::close_range(3, static_cast<unsigned>(report_fd) - 1, 0);
  ::close_range(static_cast<unsigned>(report_fd) + 1, ~0u, 0);
  Status status;
  {
    StatusOr<LoadedScene> loaded = Load(bytes);
    if (!loaded.ok()) status = loaded.status();
  }
  std::string report(1, static_cast<char>(status.code()));
  report += status.message().substr(0, kMaxReport - 1);
  WriteAll(report_fd, report.data(), report.size());
  ::_exit(0);
}

// The child's report, read until it closes the pipe or the deadline passes.
// False on the deadline.
bool ReadReport(int fd, std::chrono::steady_clock::time_point deadline, std::string& report) {
  char buffer[1024];
  for (;;) {
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    pollfd p{fd, POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(left.count()));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) return ready < 0;  // an error ends the wait as EOF would
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return true;
    if (report.size() < kMaxReport) report.append(buffer, static_cast<size_t>(n));
  }
}

int WaitFor(pid_t pid) {
  int wait_status = 0;
  while (::waitpid(pid, &wait_status, 0) < 0 && errno == EINTR) {}
  return wait_status;
}

}  // namespace

Status TrialRead(std::string_view bytes) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    return Status::Unavailable(std::string("FBX: could not start the reader's process (pipe: ") + std::strerror(errno) +
                               ")");
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int error = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    return Status::Unavailable(std::string("FBX: could not start the reader's process (fork: ") + std::strerror(error) +
                               ")");
  }
  if (pid == 0) {
    ::close(fds[0]);
    ReadAndReport(bytes, fds[1], parent);
  }
  ::close(fds[1]);
  std::string report;
  const bool in_time =
      ReadReport(fds[0], std::chrono::steady_clock::now() + std::chrono::seconds(kTrialReadSeconds), report);
  ::close(fds[0]);
  if (!in_time) ::kill(pid, SIGKILL);
  const int wait_status = WaitFor(pid);
  if (!in_time)
    return Status::InvalidArgument("FBX: assimp's reader took over " + std::to_string(kTrialReadSeconds) +
                                   " s on the file and was stopped");
  if (WIFSIGNALED(wait_status))
    return Status::InvalidArgument("FBX: assimp's reader crashed on the file (signal " +
                                   std::to_string(WTERMSIG(wait_status)) + ")");
  // Only assimp and our loader run in the child, so an end without a
  // report is the file's doing too (a sanitizer's report exits this way).
  if (report.empty())
    return Status::InvalidArgument("FBX: assimp's reader ended without a report on the file (exit status " +
                                   std::to_string(WIFEXITED(wait_status) ? WEXITSTATUS(wait_status) : -1) + ")");
  const auto code = static_cast<StatusCode>(static_cast<unsigned char>(report[0]));
  if (code == StatusCode::kOk) return Status::Ok();
  return Status(code, report.substr(1));
}

}  // namespace armature::fbx_internal
