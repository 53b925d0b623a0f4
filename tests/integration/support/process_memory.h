// A server process's memory as the kernel counts it, for tests that bound it.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <string>

namespace armature::testing {

// A field of /proc/<pid>/status in kB ("VmRSS", "VmHWM": the peak resident), -1 if absent.
int64_t StatusKb(pid_t pid, const std::string& field);

}  // namespace armature::testing
