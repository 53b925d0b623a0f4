// A process's CPU time, for tests that check the server stops working.
#pragma once

#include <sys/types.h>

namespace armature::testing {

// The CPU time `pid` has used so far (user + system), in seconds, from /proc.
double CpuSeconds(pid_t pid);

}  // namespace armature::testing
