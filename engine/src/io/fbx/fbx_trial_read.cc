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
// Memory. The child's address space may grow by the read's memory
// (TrialReadMemory) and no more: an allocation past it ends the child with
// RESOURCE_EXHAUSTED. The in-process read after a good trial allocates as
// the trial did, so the server's own read is bounded the same way. The
// cap is on the address space's growth: memory the process had freed
// before the fork is reused within it, uncounted.
//
// The cost is a second read of every good file. A failed read answers
// with assimp's message, as the in-process read did.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <new>
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

// The child's report for an allocation past its limit, written by the new
// handler, which ends the child (assimp would catch the bad_alloc and
// answer with its own vaguer message). Set only in the child.
int exhausted_fd = -1;
const std::string* exhausted_report = nullptr;

void ReportExhausted() {
  WriteAll(exhausted_fd, exhausted_report->data(), exhausted_report->size());
  ::_exit(0);
}

// The process's address space, from /proc/self/statm; 0 when unknown.
uint64_t AddressSpaceBytes() {
  const int fd = ::open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;
  char text[64] = {};
  const ssize_t n = ::read(fd, text, sizeof text - 1);
  ::close(fd);
  if (n <= 0) return 0;
  return std::strtoull(text, nullptr, 10) * static_cast<uint64_t>(::sysconf(_SC_PAGESIZE));
}

// Lets the child's address space grow by `memory_bytes` from here (a lower
// limit it inherited stays), and reports an allocation past it.
void LimitMemory(uint64_t memory_bytes, int report_fd, const std::string& report) {
  exhausted_fd = report_fd;
  exhausted_report = &report;
  std::set_new_handler(ReportExhausted);
  if (!kTrialReadLimitsMemory) return;
  const uint64_t now = AddressSpaceBytes();
  rlimit limit{};
  uint64_t cap = 0;
  if (now == 0 || ::getrlimit(RLIMIT_AS, &limit) != 0 || __builtin_add_overflow(now, memory_bytes, &cap)) return;
  if (limit.rlim_cur != RLIM_INFINITY && limit.rlim_cur <= cap) return;
  limit.rlim_cur = cap;
  ::setrlimit(RLIMIT_AS, &limit);
}

// The child: reads, reports, and leaves without running the parent's
// exit handlers or destructors (its threads are not here). It holds none
// of the parent's sockets and files, and dies with the parent's thread,
// so a server that stops is not kept on its port by a reader.
[[noreturn]] void ReadAndReport(std::string_view bytes, uint64_t memory_bytes, int report_fd, pid_t parent) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(1);  // the parent died before the line above
  if (report_fd > 3) ::close_range(3, static_cast<unsigned>(report_fd) - 1, 0);
  ::close_range(static_cast<unsigned>(report_fd) + 1, ~0u, 0);
  std::string exhausted(1, static_cast<char>(StatusCode::kResourceExhausted));
  exhausted += "FBX: assimp's read of the file needs over " + std::to_string(memory_bytes) +
               " bytes of memory, the most one FBX read may take (twice the import limit max_decoded_bytes, at "
               "least " +
               std::to_string(kTrialReadMemoryFloor >> 20) + " MB)";
  LimitMemory(memory_bytes, report_fd, exhausted);
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

uint64_t TrialReadMemory(const ImportLimits& limits) {
  uint64_t memory = 0;
  if (__builtin_mul_overflow(limits.max_decoded_bytes, 2, &memory)) return UINT64_MAX;
  return std::max(memory, kTrialReadMemoryFloor);
}

Status TrialRead(std::string_view bytes, uint64_t memory_bytes) {
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
    ReadAndReport(bytes, memory_bytes, fds[1], parent);
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
